/* Tests of vc_polymesh_face_skewness and vc_polymesh_collapse_skew_faces
 * on the Voronoi mesh of 2,000 real VoroCrust seeds of the torus (surface
 * seeds and the interior seeds near them), with a low limit so that many
 * faces collapse:
 *   - a cubic lattice has skewness 0 everywhere (centroids on the face
 *     normals through the face centres);
 *   - after the collapse: no face above the limit is left unless reported,
 *     the reported maximum is the recount, every face has >= 3 distinct
 *     points, every point is used, every cell is closed (each edge in two
 *     of its faces, in opposite directions) with positive face pyramids,
 *     the boundary faces are the same polygons on the same coordinates,
 *     and the total volume is unchanged;
 *   - a limit above every face changes nothing.
 * That checkMesh reads the same skewness is tested in e2e_foam. */
#include "vorocrust/polymesh.h"
#include "vorocrust/voronoi.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "test_check.h"

static double total_volume(const vc_polymesh *m)
{
    double v = 0;
    for (int64_t c = 0; c < m->n_cells; c++)
        v += m->cell_volume[c];
    return v;
}

static double max_skew(const vc_polymesh *m, double limit, int64_t *n_above)
{
    double w = 0;
    *n_above = 0;
    for (int64_t f = 0; f < m->n_interior_faces; f++) {
        double k = vc_polymesh_face_skewness(m, f);
        w = fmax(w, k);
        *n_above += k > limit;
    }
    return w;
}

/* Sum over the boundary faces of a hash of their coordinates, independent
 * of the point numbering. */
static double boundary_signature(const vc_polymesh *m)
{
    double sig = 0;
    for (int64_t f = m->n_interior_faces; f < m->n_faces; f++)
        for (int64_t i = m->face_offsets[f]; i < m->face_offsets[f + 1]; i++) {
            const double *p = m->points + 3 * m->face_vertices[i];
            sig += p[0] * 1.1 + p[1] * 2.3 + p[2] * 3.7 + (double)(i - m->face_offsets[f]);
        }
    return sig;
}

/* Every cell closed: each directed edge of its outward faces appears once
 * and its reverse once. Positive pyramids from the cell centroid. */
static int64_t count_open_or_inverted(const vc_polymesh *m)
{
    int64_t bad = 0;
    for (int64_t c = 0; c < m->n_cells; c++) {
        int64_t ne = 0;
        for (int64_t k = m->cell_offsets[c]; k < m->cell_offsets[c + 1]; k++)
            ne += vc_polymesh_face_size(m, m->cell_faces[k]);
        int64_t *from = malloc(sizeof(int64_t) * (size_t)ne), *to = malloc(sizeof(int64_t) * (size_t)ne);
        int64_t e = 0;
        for (int64_t k = m->cell_offsets[c]; k < m->cell_offsets[c + 1]; k++) {
            const int64_t f = m->cell_faces[k], n = vc_polymesh_face_size(m, f);
            const int64_t *fv = m->face_vertices + m->face_offsets[f];
            const int out = m->face_owner[f] == c;
            for (int64_t i = 0; i < n; i++) {
                int64_t a = fv[i], b = fv[(i + 1) % n];
                from[e] = out ? a : b;
                to[e] = out ? b : a;
                e++;
            }
            const double *fc = m->face_centroid + 3 * f, *nr = m->face_normal + 3 * f;
            const double *cc = m->cell_centroid + 3 * c;
            double h = (fc[0] - cc[0]) * nr[0] + (fc[1] - cc[1]) * nr[1] + (fc[2] - cc[2]) * nr[2];
            bad += (out ? h : -h) <= 0;
        }
        for (int64_t i = 0; i < e; i++) {
            int64_t same = 0, reverse = 0;
            for (int64_t j = 0; j < e; j++) {
                same += from[j] == from[i] && to[j] == to[i];
                reverse += from[j] == to[i] && to[j] == from[i];
            }
            bad += same != 1 || reverse != 1;
        }
        free(from);
        free(to);
    }
    return bad;
}

static int64_t count_bad_faces_and_points(const vc_polymesh *m)
{
    int64_t bad = 0;
    unsigned char *used = calloc((size_t)m->n_points + 1, 1);
    for (int64_t f = 0; f < m->n_faces; f++) {
        const int64_t n = vc_polymesh_face_size(m, f);
        const int64_t *fv = m->face_vertices + m->face_offsets[f];
        bad += n < 3;
        for (int64_t i = 0; i < n; i++) {
            used[fv[i]] = 1;
            for (int64_t j = i + 1; j < n; j++)
                bad += fv[i] == fv[j];
        }
    }
    for (int64_t v = 0; v < m->n_points; v++)
        bad += !used[v];
    free(used);
    return bad;
}

static void test_lattice(void)
{
    vc_seeds s;
    memset(&s, 0, sizeof s);
    s.n = 64;
    s.xyz = malloc(sizeof(double) * 3 * 64);
    s.label = malloc(sizeof(int32_t) * 64);
    for (int i = 0; i < 64; i++) {
        s.xyz[3 * i] = i % 4 + 0.5;
        s.xyz[3 * i + 1] = (i / 4) % 4 + 0.5;
        s.xyz[3 * i + 2] = i / 16 + 0.5;
        s.label[i] = 1;
    }
    vc_voronoi_options opt;
    vc_voronoi_options_default(&opt);
    opt.has_box = 1;
    double box[6] = {0, 0, 0, 4, 4, 4};
    memcpy(opt.box, box, sizeof box);
    vc_polymesh m;
    vc_error err = {0, ""};
    CHECK(vc_voronoi_build(&s, &opt, &m, &err) == 0);
    int64_t n_above;
    CHECK(max_skew(&m, 1e-9, &n_above) < 1e-9);
    CHECK(n_above == 0);
    vc_polymesh_free(&m);
    vc_seeds_free(&s);
}

static void test_collapse_torus_seeds(void)
{
    const char *path = VC_TEST_DATA "/torus-straight-2000.csv";
    vc_seeds s;
    vc_error err = {0, ""};
    if (vc_seeds_read_csv(path, &s, &err) != 0) {
        fprintf(stderr, "%s: %s\n", path, err.msg);
        CHECK(0);
        return;
    }
    vc_voronoi_options opt;
    vc_voronoi_options_default(&opt);
    vc_polymesh m;
    CHECK(vc_voronoi_build(&s, &opt, &m, &err) == 0);
    const double vol0 = total_volume(&m), sig0 = boundary_signature(&m);
    const int64_t nb0 = m.n_faces - m.n_interior_faces, nf0 = m.n_faces;
    int64_t above0;
    const double limit = 1.0;
    const double worst0 = max_skew(&m, limit, &above0);
    CHECK(above0 > 20); /* the test means something */

    /* a limit above every face: nothing happens */
    vc_skew_collapse_stats st;
    CHECK(vc_polymesh_collapse_skew_faces(&m, worst0 * 1.01, 10, &st) == 0);
    CHECK(st.n_collapsed == 0 && m.n_faces == nf0);
    CHECK(fabs(st.max_skew_before - worst0) <= 1e-12 * worst0);

    CHECK(vc_polymesh_collapse_skew_faces(&m, limit, 20, &st) == 0);
    int64_t above1;
    const double worst1 = max_skew(&m, limit, &above1);
    printf("torus seeds: %lld faces above skewness %g (max %.3f) -> %lld collapsed in %d rounds, "
           "%lld above left (max %.3f), largest move %.3g\n",
           (long long)above0, limit, worst0, (long long)st.n_collapsed, st.n_rounds,
           (long long)above1, worst1, st.max_move);
    CHECK(st.n_collapsed > 0);
    CHECK(above1 < above0);
    CHECK(st.n_skew_left == above1);
    CHECK(fabs(st.max_skew_after - worst1) <= 1e-12 * worst1);
    CHECK(fabs(st.max_skew_before - worst0) <= 1e-12 * worst0);
    CHECK(m.n_faces < nf0);
    CHECK(m.n_faces - m.n_interior_faces == nb0);
    CHECK(fabs(boundary_signature(&m) - sig0) <= 1e-12 * fabs(sig0));
    CHECK(fabs(total_volume(&m) - vol0) <= 1e-12 * vol0);
    CHECK(count_bad_faces_and_points(&m) == 0);
    CHECK(count_open_or_inverted(&m) == 0);
    vc_polymesh_free(&m);
    vc_seeds_free(&s);
}

int main(void)
{
    test_lattice();
    test_collapse_torus_seeds();
    if (failures) {
        fprintf(stderr, "%d check(s) failed\n", failures);
        return 1;
    }
    printf("test_skew_faces: all checks passed\n");
    return 0;
}
