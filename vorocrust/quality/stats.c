/* Summary statistics of a value array. Sorting a copy makes every figure
 * independent of the order (and thread count) the values were made in. */
#include "vorocrust/quality.h"

#include <math.h>
#include <stdlib.h>
#include <stdint.h>
#include <string.h>

enum { RADIX_BITS = 16, RADIX_BUCKETS = 1 << RADIX_BITS };

/* Sorts v[0 .. n) ascending (no NaN) by a radix sort of the values' bits,
 * mapped so that their unsigned order is the numeric order (negative
 * values: every bit flipped; others: the sign bit set); tmp holds n values
 * and count RADIX_BUCKETS. Linear time: a mesh's faces number in the
 * millions. */
static void sort_doubles(double *v, double *tmp, int64_t *count, int64_t n)
{
    uint64_t *a = (uint64_t *)v, *b = (uint64_t *)tmp;
    for (int64_t i = 0; i < n; i++) {
        uint64_t u;
        memcpy(&u, &v[i], sizeof u);
        a[i] = (u >> 63) ? ~u : u | (UINT64_C(1) << 63);
    }
    for (int pass = 0; pass < 64 / RADIX_BITS; pass++) {
        const int shift = pass * RADIX_BITS;
        memset(count, 0, sizeof(int64_t) * RADIX_BUCKETS);
        for (int64_t i = 0; i < n; i++)
            count[(a[i] >> shift) & (RADIX_BUCKETS - 1)]++;
        int64_t sum = 0;
        for (int64_t k = 0; k < RADIX_BUCKETS; k++) {
            const int64_t c = count[k];
            count[k] = sum;
            sum += c;
        }
        for (int64_t i = 0; i < n; i++)
            b[count[(a[i] >> shift) & (RADIX_BUCKETS - 1)]++] = a[i];
        uint64_t *t = a;
        a = b;
        b = t;
    }
    /* an even number of passes: the keys are back in v */
    for (int64_t i = 0; i < n; i++) {
        const uint64_t u = (a[i] >> 63) ? a[i] & ~(UINT64_C(1) << 63) : ~a[i];
        memcpy(&v[i], &u, sizeof u);
    }
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
    double *s = malloc(sizeof *s * 2 * (size_t)n);
    int64_t *count = malloc(sizeof *count * RADIX_BUCKETS);
    if (!s || !count) {
        free(s);
        free(count);
        return VC_ENOMEM;
    }
    int64_t k = 0;
    for (int64_t i = 0; i < n; i++)
        if (!isnan(values[i]))
            s[k++] = values[i];
    if (k > 0) {
        sort_doubles(s, s + n, count, k);
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
    free(count);
    return VC_OK;
}
