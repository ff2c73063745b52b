/* Summary statistics of a value array. Sorting a copy makes every figure
 * independent of the order (and thread count) the values were made in. */
#include "vorocrust/quality.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static int cmp_double(const void *x, const void *y)
{
    double a = *(const double *)x, b = *(const double *)y;
    return (a > b) - (a < b);
}

double vc_percentile_sorted(const double *sorted, int64_t n, double q)
{
    if (n <= 0)
        return NAN;
    double h = (double)(n - 1) * (q / 100.0);
    if (h <= 0)
        return sorted[0];
    if (h >= (double)(n - 1))
        return sorted[n - 1];
    int64_t lo = (int64_t)floor(h);
    double frac = h - (double)lo;
    if (frac == 0 || sorted[lo] == sorted[lo + 1])
        return sorted[lo]; /* also keeps infinities out of inf - inf */
    return sorted[lo] + frac * (sorted[lo + 1] - sorted[lo]);
}

int vc_stats_compute(const double *values, int64_t n, vc_stats *out)
{
    out->n = 0;
    out->min = out->max = out->mean = NAN;
    out->p1 = out->p5 = out->p50 = out->p95 = out->p99 = NAN;
    if (n <= 0)
        return VC_OK;
    double *s = malloc(sizeof *s * (size_t)n);
    if (!s)
        return VC_ENOMEM;
    int64_t k = 0;
    for (int64_t i = 0; i < n; i++)
        if (!isnan(values[i]))
            s[k++] = values[i];
    if (k > 0) {
        qsort(s, (size_t)k, sizeof *s, cmp_double);
        double sum = 0;
        for (int64_t i = 0; i < k; i++)
            sum += s[i];
        out->n = k;
        out->min = s[0];
        out->max = s[k - 1];
        out->mean = sum / (double)k;
        out->p1 = vc_percentile_sorted(s, k, 1);
        out->p5 = vc_percentile_sorted(s, k, 5);
        out->p50 = vc_percentile_sorted(s, k, 50);
        out->p95 = vc_percentile_sorted(s, k, 95);
        out->p99 = vc_percentile_sorted(s, k, 99);
    }
    free(s);
    return VC_OK;
}
