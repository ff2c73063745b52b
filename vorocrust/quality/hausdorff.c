/* Two-sided Hausdorff distance between triangle surfaces.
 *
 * Samples: the barycentric grid of every triangle with n = ceil(longest
 * edge / spacing) subdivisions per edge (its corners are the vertices, its
 * border points the edge points). Every point of the triangle is then
 * within the circumradius-like bound (longest edge / n) / sqrt(3) of a
 * grid point (the farthest point from the corners of a triangle with
 * longest edge l is at most l / sqrt(3) away from them).
 *
 * Distances to the other surface: a bounding-volume hierarchy over its
 * triangles, split at the median centroid along the longest axis (a
 * balanced tree, no tuning), queried nearest-child first with pruning on
 * box distance. A sample closer to the
 * other surface than the running maximum cannot change the result, so its
 * search stops at the first triangle that close (usually the previous
 * sample's nearest triangle), and whole triangles are skipped when a
 * Lipschitz bound from their corners shows they cannot hold the maximum. */
#include "vorocrust/quality.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "quality/vec3.h"
#include "quality/quality_internal.h"
#include "util/triangle_bvh.h"
#include "util/threads.h"

#define SAMPLE_BUDGET 1000000.0

static double tri_longest_edge(const vc_surface *s, int64_t t)
{
    const double *a = s->xyz + 3 * s->tri[3 * t], *b = s->xyz + 3 * s->tri[3 * t + 1],
                 *c = s->xyz + 3 * s->tri[3 * t + 2];
    return sqrt(fmax(v3_dist2(a, b), fmax(v3_dist2(b, c), v3_dist2(c, a))));
}

static int64_t subdivisions(double longest, double spacing)
{
    double n = ceil(longest / spacing);
    return n < 1 ? 1 : n > 1e6 ? 1000000 : (int64_t)n;
}

static double count_samples(const vc_surface *s, double spacing)
{
    double total = 0;
    for (int64_t t = 0; t < s->n_triangles; t++) {
        double n = (double)subdivisions(tri_longest_edge(s, t), spacing);
        total += (n + 1) * (n + 2) / 2;
    }
    return total;
}

/* max over the samples of `from` of the distance to the hierarchy `to`;
 * -1 when out of memory.
 *
 * First the exact distance of every vertex (they are samples). Since the
 * distance is 1-Lipschitz and every point of a triangle with longest edge
 * l is within l / sqrt(3) of a corner, no sample of a triangle can exceed
 * max(corner distances) + l / sqrt(3); a triangle whose bound is below the
 * running maximum is skipped whole. Skipped samples and early-stopped
 * searches can never hold the maximum, so the result is exactly the
 * maximum over all samples, whatever the thread count or order. */
static double one_sided(const vc_surface *from, const vc_tri_bvh *to, double spacing, int nth,
                        int64_t *n_samples, double *sub_edge)
{
    const int64_t nv = from->n_vertices, nt = from->n_triangles;
    double *dv = malloc(sizeof *dv * (size_t)(nv ? nv : 1));
    int64_t *near_tri = malloc(sizeof *near_tri * (size_t)(nv ? nv : 1));
    if (!dv || !near_tri) {
        free(dv);
        free(near_tri);
        return -1;
    }
    for (int64_t v = 0; v < nv; v++)
        near_tri[v] = -2; /* not a corner of any triangle: not a sample */
    for (int64_t k = 0; k < 3 * nt; k++)
        near_tri[from->tri[k]] = -1;
    double vmax = 0;
#pragma omp parallel for schedule(dynamic, 1024) reduction(max : vmax) num_threads(nth)
    for (int64_t v = 0; v < nv; v++) {
        dv[v] = 0;
        if (near_tri[v] == -2)
            continue;
        dv[v] = vc_tri_bvh_distance_above(to, from->xyz + 3 * v, -1.0, &near_tri[v]);
        if (dv[v] > vmax)
            vmax = dv[v];
    }
    double worst = 0, longest_sub = 0;
    int64_t count = 0;
#pragma omp parallel for schedule(dynamic, 256) reduction(max : worst, longest_sub) reduction(+ : count) num_threads(nth)
    for (int64_t t = 0; t < nt; t++) {
        const int64_t *id = from->tri + 3 * t;
        const double *a = from->xyz + 3 * id[0], *b = from->xyz + 3 * id[1], *c = from->xyz + 3 * id[2];
        double longest = tri_longest_edge(from, t);
        int64_t n = subdivisions(longest, spacing);
        if (longest / (double)n > longest_sub)
            longest_sub = longest / (double)n; /* <= spacing unless n hit its cap */
        count += (n + 1) * (n + 2) / 2;
        double floor_ = worst > vmax ? worst : vmax;
        double corner = fmax(dv[id[0]], fmax(dv[id[1]], dv[id[2]]));
        if (corner + longest / sqrt(3.0) <= floor_)
            continue;
        int64_t hint = near_tri[id[0]]; /* neighbouring samples share their nearest triangle */
        for (int64_t i = 0; i <= n; i++)
            for (int64_t j = 0; i + j <= n; j++) {
                double u = (double)i / (double)n, v = (double)j / (double)n, w = 1.0 - u - v;
                double p[3];
                for (int d = 0; d < 3; d++)
                    p[d] = w * a[d] + u * b[d] + v * c[d];
                /* only a sample beyond this thread's maximum matters, so
                 * the search may stop at the first triangle that close */
                double dist = vc_tri_bvh_distance_above(to, p, floor_, &hint);
                if (dist > floor_)
                    floor_ = dist;
            }
        if (floor_ > worst)
            worst = floor_;
    }
    free(dv);
    free(near_tri);
    *n_samples = count;
    *sub_edge = longest_sub;
    return worst > vmax ? worst : vmax;
}

static double bbox_diagonal(const vc_surface *s)
{
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int64_t t = 0; t < 3 * s->n_triangles; t++)
        for (int d = 0; d < 3; d++) {
            lo[d] = fmin(lo[d], s->xyz[3 * s->tri[t] + d]);
            hi[d] = fmax(hi[d], s->xyz[3 * s->tri[t] + d]);
        }
    double e[3] = {hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]};
    return v3_norm(e);
}

int vc_hausdorff(const vc_surface *a, const vc_surface *b, double spacing,
                 vc_hausdorff_result *out, vc_error *err)
{
    return vc_hausdorff_threads(a, b, spacing, 0, out, err);
}

int vc_hausdorff_threads(const vc_surface *a, const vc_surface *b, double spacing, int threads,
                         vc_hausdorff_result *out, vc_error *err)
{
    const int nth = vc_threads_or_default(threads);
    memset(out, 0, sizeof *out);
    if (!a || !b || a->n_triangles < 1 || b->n_triangles < 1)
        return vc_error_set(err, VC_EINPUT, "Hausdorff distance: a surface has no triangle");
    double diag = bbox_diagonal(a);
    if (!(spacing > 0)) {
        spacing = diag > 0 ? 1e-3 * diag : 1.0;
        /* Coarsen until neither side exceeds the budget (samples scale as
         * 1 / spacing^2, plus at least 3 per triangle). */
        for (int it = 0; it < 40; it++) {
            double na = count_samples(a, spacing), nb = count_samples(b, spacing);
            double worst = fmax(na, nb);
            double floor_samples = 3.0 * (double)(a->n_triangles > b->n_triangles ? a->n_triangles
                                                                                   : b->n_triangles);
            if (worst <= SAMPLE_BUDGET || worst <= 1.05 * floor_samples)
                break;
            spacing *= fmax(1.1, sqrt(worst / SAMPLE_BUDGET));
        }
    }
    vc_tri_bvh ha, hb;
    memset(&hb, 0, sizeof hb);
    int rc = vc_tri_bvh_build(&ha, a->xyz, a->tri, a->n_triangles, nth);
    if (!rc)
        rc = vc_tri_bvh_build(&hb, b->xyz, b->tri, b->n_triangles, nth);
    if (rc) {
        vc_tri_bvh_free(&ha);
        vc_tri_bvh_free(&hb);
        return vc_error_set(err, VC_ENOMEM, "Hausdorff distance: out of memory");
    }
    double sub_a = 0, sub_b = 0;
    out->a_to_b = one_sided(a, &hb, spacing, nth, &out->n_samples_a, &sub_a);
    out->b_to_a = one_sided(b, &ha, spacing, nth, &out->n_samples_b, &sub_b);
    vc_tri_bvh_free(&ha);
    vc_tri_bvh_free(&hb);
    if (out->a_to_b < 0 || out->b_to_a < 0)
        return vc_error_set(err, VC_ENOMEM, "Hausdorff distance: out of memory");
    out->distance = fmax(out->a_to_b, out->b_to_a);
    out->diagonal = diag;
    out->normalised = diag > 0 ? out->distance / diag : 0;
    out->spacing = spacing;
    /* the longest edge of any sampling sub-triangle, over sqrt(3) */
    out->error_bound = dmax(sub_a, sub_b) / sqrt(3.0);
    return VC_OK;
}
