/* Tests of feature detection (vorocrust/features.h): known answers on the
 * reference models and on small built surfaces, and the structural
 * invariants (every triangle in one patch, every sharp edge in one crease,
 * crease ends at corners, consistent patch orientation, edge index
 * against a brute-force one) on every input. Environment: VC_MODELS (the
 * shared models). */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "vorocrust/features.h"
#include "vorocrust/surface.h"

#include "test_check.h"
#include "test_surface_util.h"

/* ---- Building small surfaces in memory. ---- */

/* The four triangles of the tetrahedron v[0..3], consistently oriented. */
static void add_tet(builder *b, const int64_t v[4])
{
    add_t(b, v[0], v[2], v[1]);
    add_t(b, v[0], v[1], v[3]);
    add_t(b, v[1], v[2], v[3]);
    add_t(b, v[2], v[0], v[3]);
}

/* ---- Invariants that hold on every input. ---- */

static int64_t other_end(const vc_features *f, int64_t e, int64_t v)
{
    return f->edge_vertex[2 * e] == v ? f->edge_vertex[2 * e + 1] : f->edge_vertex[2 * e];
}

static void check_invariants(const char *name, const vc_surface *s, const vc_features *f)
{
    int64_t nv = s->n_vertices, nt = s->n_triangles, ne = f->n_edges;
    CHECKF(f->n_vertices == nv && f->n_triangles == nt, "%s: sizes", name);

    /* Edge index: every side of every triangle is its edge, listed once
     * among the edge's triangles; edges sorted and unique. */
    int64_t bad_side = 0, bad_list = 0, bad_find = 0;
    for (int64_t t = 0; t < nt; t++)
        for (int j = 0; j < 3; j++) {
            int64_t a = s->tri[3 * t + j], b = s->tri[3 * t + (j + 1) % 3];
            int64_t e = f->tri_edge[3 * t + j];
            if (e < 0 || e >= ne || f->edge_vertex[2 * e] != (a < b ? a : b) ||
                f->edge_vertex[2 * e + 1] != (a < b ? b : a))
                bad_side++;
            else {
                int n = 0;
                for (int64_t k = f->edge_tri_start[e]; k < f->edge_tri_start[e + 1]; k++)
                    n += f->edge_tri[k] == t;
                bad_list += n != 1;
            }
            bad_find += vc_features_find_edge(f, b, a) != e;
        }
    CHECKF(bad_side == 0 && bad_list == 0 && bad_find == 0, "%s: edge index: %lld bad sides, %lld bad lists, %lld bad finds",
          name, (long long)bad_side, (long long)bad_list, (long long)bad_find);
    CHECKF(f->edge_tri_start[0] == 0 && f->edge_tri_start[ne] == 3 * nt, "%s: edge_tri_start", name);
    int64_t unsorted = 0;
    for (int64_t e = 0; e < ne; e++) {
        unsorted += f->edge_vertex[2 * e] >= f->edge_vertex[2 * e + 1];
        if (e > 0)
            unsorted += f->edge_vertex[2 * e - 2] > f->edge_vertex[2 * e] ||
                        (f->edge_vertex[2 * e - 2] == f->edge_vertex[2 * e] &&
                         f->edge_vertex[2 * e - 1] >= f->edge_vertex[2 * e + 1]);
        unsorted += f->edge_tri_start[e + 1] <= f->edge_tri_start[e];
    }
    CHECKF(unsorted == 0, "%s: %lld edge order violations", name, (long long)unsorted);
    CHECKF(vc_features_find_edge(f, 0, 0) == -1, "%s: find_edge(0, 0)", name);

    /* Sharp edges: reasons agree with the triangle count. */
    int64_t n_sharp = 0, n_b = 0, n_nm = 0, bad_reason = 0;
    for (int64_t e = 0; e < ne; e++) {
        int64_t m = f->edge_tri_start[e + 1] - f->edge_tri_start[e];
        n_sharp += f->edge_sharp[e] != 0;
        n_b += m == 1;
        n_nm += m > 2;
        if (m == 1)
            bad_reason += f->edge_sharp[e] != VC_SHARP_BOUNDARY;
        else if (m > 2)
            bad_reason += f->edge_sharp[e] != VC_SHARP_NONMANIFOLD;
        else
            bad_reason += f->edge_sharp[e] != 0 && f->edge_sharp[e] != VC_SHARP_ANGLE;
    }
    CHECKF(n_sharp == f->n_sharp_edges && n_b == f->n_boundary_edges && n_nm == f->n_nonmanifold_edges &&
              bad_reason == 0 && f->n_sharp_edges == f->n_sharp_by_angle + n_b + n_nm,
          "%s: sharp counts %lld/%lld, boundary %lld/%lld, non-manifold %lld/%lld, %lld bad reasons", name,
          (long long)n_sharp, (long long)f->n_sharp_edges, (long long)n_b, (long long)f->n_boundary_edges,
          (long long)n_nm, (long long)f->n_nonmanifold_edges, (long long)bad_reason);

    /* Corners: degree rules. */
    int32_t *deg = calloc((size_t)nv + 1, sizeof *deg);
    for (int64_t e = 0; e < ne; e++)
        if (f->edge_sharp[e]) {
            deg[f->edge_vertex[2 * e]]++;
            deg[f->edge_vertex[2 * e + 1]]++;
        }
    int64_t n_corners = 0, bad_deg = 0;
    for (int64_t v = 0; v < nv; v++) {
        n_corners += f->vertex_corner[v] != 0;
        bad_deg += deg[v] != f->vertex_sharp_degree[v];
        if (deg[v] == 1 || deg[v] > 2)
            bad_deg += f->vertex_corner[v] == 0;
        bad_deg += ((f->vertex_corner[v] & VC_CORNER_DEGREE) != 0) != (deg[v] > 2);
        bad_deg += ((f->vertex_corner[v] & VC_CORNER_END) != 0) != (deg[v] == 1);
        bad_deg += (f->vertex_corner[v] & VC_CORNER_TURN) && deg[v] != 2;
        bad_deg += (f->vertex_corner[v] & VC_CORNER_PINCH) && deg[v] != 0;
    }
    CHECKF(n_corners == f->n_corners && bad_deg == 0, "%s: corners %lld/%lld, %lld degree violations", name,
          (long long)n_corners, (long long)f->n_corners, (long long)bad_deg);

    /* Creases: every sharp edge in exactly one crease, walked in order;
     * ends at corners unless closed; no corner inside a crease. */
    int64_t *seen = calloc((size_t)ne + 1, sizeof *seen);
    int64_t bad_crease = 0, n_closed = 0;
    CHECKF(f->crease_start[0] == 0 && f->crease_start[f->n_creases] == f->n_sharp_edges, "%s: crease_start", name);
    for (int64_t c = 0; c < f->n_creases; c++) {
        int64_t k = vc_crease_n_edges(f, c);
        const int64_t *vv = vc_crease_vertices(f, c);
        const int64_t *ee = f->crease_edge + f->crease_start[c];
        bad_crease += k < 1;
        n_closed += f->crease_closed[c] != 0;
        for (int64_t i = 0; i < k; i++) {
            int64_t e = ee[i];
            seen[e]++;
            bad_crease += !f->edge_sharp[e] || f->edge_crease[e] != c;
            int dir = f->edge_crease_dir[e];
            int64_t from = dir > 0 ? f->edge_vertex[2 * e] : f->edge_vertex[2 * e + 1];
            bad_crease += (dir != 1 && dir != -1) || from != vv[i] || other_end(f, e, from) != vv[i + 1];
            if (i > 0)
                bad_crease += f->vertex_corner[vv[i]] != 0;
        }
        if (f->crease_closed[c])
            bad_crease += vv[0] != vv[k] || f->vertex_corner[vv[0]] != 0;
        else
            bad_crease += !f->vertex_corner[vv[0]] || !f->vertex_corner[vv[k]] || vv[0] > vv[k];
        if (c > 0 && !f->crease_closed[c])
            bad_crease += f->crease_closed[c - 1] || vc_crease_vertices(f, c - 1)[0] > vv[0];
    }
    for (int64_t e = 0; e < ne; e++) {
        if (f->edge_sharp[e])
            bad_crease += seen[e] != 1;
        else
            bad_crease += seen[e] != 0 || f->edge_crease[e] != -1 || f->edge_crease_dir[e] != 0;
    }
    CHECKF(bad_crease == 0 && n_closed == f->n_closed_creases, "%s: %lld crease violations, closed %lld/%lld", name,
          (long long)bad_crease, (long long)n_closed, (long long)f->n_closed_creases);
    free(seen);

    /* Patches: every triangle in exactly one; non-sharp edges inside one
     * patch and walked in opposite directions by the oriented triangles;
     * normals in the patch orientation. */
    int64_t *count = calloc((size_t)nt + 1, sizeof *count);
    int64_t bad_patch = 0, bad_orient = 0, bad_normal = 0, n_nonorientable = 0;
    CHECKF(f->patch_start[0] == 0 && f->patch_start[f->n_patches] == nt, "%s: patch_start", name);
    for (int64_t p = 0; p < f->n_patches; p++) {
        bad_patch += f->patch_start[p + 1] <= f->patch_start[p];
        n_nonorientable += !f->patch_orientable[p];
        for (int64_t k = f->patch_start[p]; k < f->patch_start[p + 1]; k++) {
            int64_t t = f->patch_tri[k];
            count[t]++;
            bad_patch += f->tri_patch[t] != p;
            if (k > f->patch_start[p])
                bad_patch += f->patch_tri[k - 1] >= t;
        }
        if (p > 0)
            bad_patch += f->patch_tri[f->patch_start[p - 1]] >= f->patch_tri[f->patch_start[p]];
    }
    for (int64_t t = 0; t < nt; t++)
        bad_patch += count[t] != 1;
    for (int64_t e = 0; e < ne; e++) {
        if (f->edge_sharp[e])
            continue;
        int64_t t1 = f->edge_tri[f->edge_tri_start[e]], t2 = f->edge_tri[f->edge_tri_start[e] + 1];
        bad_patch += f->tri_patch[t1] != f->tri_patch[t2];
        if (!f->patch_orientable[f->tri_patch[t1]])
            continue;
        int dirs[2];
        for (int q = 0; q < 2; q++) {
            int64_t v[3];
            vc_features_oriented_triangle(f, s, q ? t2 : t1, v);
            dirs[q] = 0;
            for (int j = 0; j < 3; j++)
                if (v[j] == f->edge_vertex[2 * e] && v[(j + 1) % 3] == f->edge_vertex[2 * e + 1])
                    dirs[q] = 1;
                else if (v[j] == f->edge_vertex[2 * e + 1] && v[(j + 1) % 3] == f->edge_vertex[2 * e])
                    dirs[q] = -1;
        }
        bad_orient += dirs[0] == 0 || dirs[0] != -dirs[1];
    }
    for (int64_t t = 0; t < nt; t++) {
        int64_t v[3];
        vc_features_oriented_triangle(f, s, t, v);
        const double *a = s->xyz + 3 * v[0], *b = s->xyz + 3 * v[1], *c = s->xyz + 3 * v[2];
        double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, w[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
        double n[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
        const double *m = f->tri_normal + 3 * t;
        double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        double mlen = sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]);
        if (mlen == 0)
            continue;
        bad_normal += fabs(mlen - 1) > 1e-12 || (n[0] * m[0] + n[1] * m[1] + n[2] * m[2]) < (1 - 1e-9) * len;
        bad_orient += f->tri_orient[t] != 1 && f->tri_orient[t] != -1;
    }
    CHECKF(bad_patch == 0 && bad_orient == 0 && bad_normal == 0 && n_nonorientable == f->n_nonorientable_patches,
          "%s: %lld patch violations, %lld orientation violations, %lld bad normals", name, (long long)bad_patch,
          (long long)bad_orient, (long long)bad_normal);
    free(count);
    free(deg);
}

static int detect(const char *name, const vc_surface *s, double theta, vc_features *f)
{
    vc_error err = {0, ""};
    int rc = vc_features_detect(s, theta, f, &err);
    CHECKF(rc == 0, "%s: detect at %g failed: %s", name, theta, err.msg);
    if (rc == 0)
        check_invariants(name, s, f);
    return rc == 0;
}

static void expect(const char *name, const vc_features *f, int64_t sharp, int64_t corners, int64_t creases,
                   int64_t closed, int64_t patches)
{
    CHECKF(f->n_sharp_edges == sharp && f->n_corners == corners && f->n_creases == creases &&
              f->n_closed_creases == closed && f->n_patches == patches,
          "%s at %g: sharp %lld corners %lld creases %lld (closed %lld) patches %lld; expected %lld %lld %lld (%lld) %lld",
          name, f->sharp_angle, (long long)f->n_sharp_edges, (long long)f->n_corners, (long long)f->n_creases,
          (long long)f->n_closed_creases, (long long)f->n_patches, (long long)sharp, (long long)corners,
          (long long)creases, (long long)closed, (long long)patches);
}

/* ---- The reference models. ---- */

typedef struct model_case {
    const char *file;
    /* Expected at the default angle; -1: not checked. */
    int64_t sharp, corners, creases, closed, patches;
} model_case;

static void test_models(const char *models)
{
    /* cube, onebox: 12 edges of a box, 8 corners, one crease per edge, a
     * patch per face. bracket: derived in tests/e2e_features.py (every
     * 90-degree edge; 16 corners where three sharp edges meet and 16 at
     * the 45-degree tips of the 8 triangular rib faces; 24 rib creases +
     * 6 wall/base junction pieces + 10 outline creases; 8 rib faces, the
     * base-top/rib-slope/inner-wall patch, the side-and-top band, the two
     * outer end faces and the bottom). fertility: the 6 edges of a coarse
     * scan whose normals differ by more than 60 degrees (60.2 to 80.9);
     * no loop, so one patch. */
    const model_case cases[] = {
        {"cube.off", 12, 8, 12, 0, 6},
        {"onebox.obj", 12, 8, 12, 0, 6},
        {"bracket.obj", 270, 32, 40, 0, 13},
        {"sphere.obj", 0, 0, 0, 0, 1},
        {"torus.obj", 0, 0, 0, 0, 1},
        {"fertility.off", 6, -1, 5, 0, 1},
        {"fandisk.off", -1, -1, -1, -1, -1},
        {"bumpy-cube.obj", 0, 0, 0, 0, 1},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        const model_case *c = &cases[i];
        char path[1024];
        snprintf(path, sizeof path, "%s/%s", models, c->file);
        vc_surface s;
        vc_surface_report r;
        vc_error err = {0, ""};
        if (vc_surface_read(path, &s, &r, &err)) {
            CHECKF(0, "%s: %s", path, err.msg);
            continue;
        }
        vc_features f;
        if (!detect(c->file, &s, VC_FEATURES_DEFAULT_SHARP_ANGLE, &f)) {
            vc_surface_free(&s);
            continue;
        }
        CHECKF(f.n_edges == r.n_edges, "%s: %lld edges, the check counted %lld", c->file, (long long)f.n_edges,
              (long long)r.n_edges);
        if (c->sharp >= 0)
            CHECKF(f.n_sharp_edges == c->sharp, "%s: %lld sharp edges, expected %lld", c->file,
                  (long long)f.n_sharp_edges, (long long)c->sharp);
        if (c->corners >= 0)
            CHECKF(f.n_corners == c->corners, "%s: %lld corners, expected %lld", c->file, (long long)f.n_corners,
                  (long long)c->corners);
        if (c->creases >= 0)
            CHECKF(f.n_creases == c->creases && f.n_closed_creases == c->closed,
                  "%s: %lld creases (%lld closed), expected %lld (%lld)", c->file, (long long)f.n_creases,
                  (long long)f.n_closed_creases, (long long)c->creases, (long long)c->closed);
        if (c->patches >= 0)
            CHECKF(f.n_patches == c->patches, "%s: %lld patches, expected %lld", c->file, (long long)f.n_patches,
                  (long long)c->patches);
        /* A closed, consistently oriented input keeps its orientation. */
        int64_t flipped = 0;
        for (int64_t t = 0; t < s.n_triangles; t++)
            flipped += f.tri_orient[t] != 1;
        CHECKF(flipped == 0 && f.n_nonorientable_patches == 0, "%s: %lld triangles flipped", c->file,
              (long long)flipped);

        if (!strcmp(c->file, "cube.off") || !strcmp(c->file, "onebox.obj")) {
            /* The quad diagonals are not sharp: every sharp edge is a box
             * edge (cube.off: length^2 2, diagonals 4; onebox: 1 and 2). */
            int cube = !strcmp(c->file, "cube.off");
            int64_t bad = 0;
            for (int64_t e = 0; e < f.n_edges; e++) {
                const double *a = s.xyz + 3 * f.edge_vertex[2 * e], *b = s.xyz + 3 * f.edge_vertex[2 * e + 1];
                double d[3] = {fabs(a[0] - b[0]), fabs(a[1] - b[1]), fabs(a[2] - b[2])};
                int n_axes = (d[0] > 0) + (d[1] > 0) + (d[2] > 0);
                /* cube.off: a sqrt(2) x sqrt(2) x 2 box turned 45 degrees
                 * about z: vertical edges, and horizontal ones of length
                 * sqrt(2) (top and bottom diagonals have length 2). onebox:
                 * axis-aligned edges. */
                int box_edge = cube ? (d[0] == 0 && d[1] == 0) ||
                                          (d[2] == 0 && fabs(d[0] * d[0] + d[1] * d[1] - 2) < 1e-12)
                                    : n_axes == 1;
                bad += (f.edge_sharp[e] != 0) != box_edge;
            }
            CHECKF(bad == 0, "%s: %lld edges sharp iff box edge violated", c->file, (long long)bad);
            for (int64_t p = 0; p < f.n_patches; p++)
                CHECKF(f.patch_start[p + 1] - f.patch_start[p] == 2, "%s: patch %lld size", c->file, (long long)p);
            for (int64_t v = 0; v < f.n_vertices; v++)
                CHECKF(f.vertex_corner[v] == VC_CORNER_DEGREE && f.vertex_sharp_degree[v] == 3,
                      "%s: vertex %lld corner %d degree %d", c->file, (long long)v, f.vertex_corner[v],
                      f.vertex_sharp_degree[v]);
        }
        if (!strcmp(c->file, "bracket.obj")) {
            int64_t degree = 0, turn = 0;
            for (int64_t v = 0; v < f.n_vertices; v++) {
                degree += f.vertex_corner[v] == VC_CORNER_DEGREE;
                turn += f.vertex_corner[v] == VC_CORNER_TURN;
            }
            CHECKF(degree == 16 && turn == 16, "bracket: %lld degree corners, %lld turn corners", (long long)degree,
                  (long long)turn);
        }
        if (!strcmp(c->file, "fertility.off")) {
            /* Crease ends are corners (also by the sector rule, since the
             * edges are sharp by angle). */
            int64_t ends = 0;
            for (int64_t v = 0; v < f.n_vertices; v++)
                if (f.vertex_sharp_degree[v] == 1) {
                    ends++;
                    CHECKF(f.vertex_corner[v] == (VC_CORNER_END | VC_CORNER_SECTOR), "fertility: end %lld why %d",
                          (long long)v, f.vertex_corner[v]);
                }
            CHECKF(ends == 10, "fertility: %lld crease ends", (long long)ends);
        }

        /* Monotone in theta: a smaller threshold keeps every sharp edge
         * and every corner-free surface gets no fewer sharp edges. */
        vc_features prev;
        int have_prev = 0;
        for (double th = 170; th >= 9.9; th -= 20) {
            vc_features g;
            char name[128];
            snprintf(name, sizeof name, "%s at %g", c->file, th);
            if (!detect(name, &s, th, &g))
                break;
            if (have_prev) {
                int64_t lost = 0;
                for (int64_t e = 0; e < g.n_edges; e++)
                    lost += prev.edge_sharp[e] && !g.edge_sharp[e];
                CHECKF(lost == 0 && g.n_sharp_edges >= prev.n_sharp_edges,
                      "%s: %lld sharp edges at %g, %lld at %g (%lld lost)", c->file, (long long)g.n_sharp_edges, th,
                      (long long)prev.n_sharp_edges, th + 20, (long long)lost);
                vc_features_free(&prev);
            }
            prev = g;
            have_prev = 1;
        }
        if (have_prev)
            vc_features_free(&prev);
        vc_features_free(&f);
        vc_surface_free(&s);
    }
}

/* ---- Built surfaces. ---- */

static void test_tets_sharing_edge(void)
{
    /* Two regular-ish tetrahedra sharing the edge 0-1: that edge has four
     * triangles. */
    builder b = {0};
    add_v(&b, 0, 0, 0);
    add_v(&b, 1, 0, 0);
    add_v(&b, 0.5, 1, 0.2);
    add_v(&b, 0.5, 0.3, 1);
    add_v(&b, 0.5, -1, 0.2);
    add_v(&b, 0.5, -0.3, -1);
    const int64_t t1[4] = {0, 1, 2, 3}, t2[4] = {1, 0, 4, 5};
    add_tet(&b, t1);
    add_tet(&b, t2);
    vc_features f;
    if (detect("two tets", &b.s, 60, &f)) {
        /* All 11 edges sharp (tetrahedron dihedral angles are below 120
         * degrees), every vertex a corner, 11 one-edge creases, a patch
         * per triangle. */
        expect("two tets", &f, 11, 6, 11, 0, 8);
        int64_t e = vc_features_find_edge(&f, 1, 0);
        CHECKF(e >= 0 && f.edge_sharp[e] == VC_SHARP_NONMANIFOLD && f.edge_tri_start[e + 1] - f.edge_tri_start[e] == 4,
              "two tets: shared edge %lld sharp %d", (long long)e, e >= 0 ? f.edge_sharp[e] : -1);
        CHECKF(f.n_nonmanifold_edges == 1 && f.n_boundary_edges == 0, "two tets: edge kinds");
        vc_features_free(&f);
    }
    if (detect("two tets at 150", &b.s, 150, &f)) {
        /* Only the non-manifold edge is sharp: one crease between two
         * crease-end corners; each tetrahedron is a patch. */
        expect("two tets at 150", &f, 1, 2, 1, 0, 2);
        int64_t e = vc_features_find_edge(&f, 0, 1);
        CHECKF(e >= 0 && f.edge_sharp[e] == VC_SHARP_NONMANIFOLD && f.edge_crease[e] == 0, "two tets at 150: edge");
        CHECKF(f.vertex_corner[0] == VC_CORNER_END && f.vertex_corner[1] == VC_CORNER_END,
              "two tets at 150: corners %d %d", f.vertex_corner[0], f.vertex_corner[1]);
        CHECKF(f.tri_patch[0] != f.tri_patch[4], "two tets at 150: one patch per tetrahedron");
        vc_features_free(&f);
    }
    vc_surface_free(&b.s);
}

static void test_pinch(void)
{
    /* Two tetrahedra touching at vertex 0 only. */
    builder b = {0};
    add_v(&b, 0, 0, 0);
    add_v(&b, 1, 0.1, 0.2);
    add_v(&b, 1, 1, -0.1);
    add_v(&b, 1, -0.2, 1);
    add_v(&b, -1, 0.1, 0.2);
    add_v(&b, -1, 1, -0.1);
    add_v(&b, -1, -0.2, 1);
    const int64_t t1[4] = {0, 1, 2, 3}, t2[4] = {0, 5, 4, 6};
    add_tet(&b, t1);
    add_tet(&b, t2);
    vc_features f;
    if (detect("pinch", &b.s, 170, &f)) {
        expect("pinch", &f, 0, 1, 0, 0, 2);
        CHECKF(f.vertex_corner[0] == VC_CORNER_PINCH, "pinch: vertex 0 corner %d", f.vertex_corner[0]);
        vc_features_free(&f);
    }
    vc_surface_free(&b.s);
}

static void test_prism(void)
{
    /* A 12-gon prism: neighbouring sides differ by 30 degrees. */
    builder b = {0};
    make_prism(&b, 12, 0.7);
    vc_features f;
    if (detect("prism", &b.s, 60, &f)) {
        /* The two rims are closed creases without corners (they turn by
         * 30 degrees at each vertex); caps and side band are patches. */
        expect("prism", &f, 24, 0, 2, 2, 3);
        for (int64_t c = 0; c < f.n_creases; c++)
            CHECKF(vc_crease_n_edges(&f, c) == 12 && f.crease_closed[c], "prism: crease %lld", (long long)c);
        vc_features_free(&f);
    }
    if (detect("prism at 20", &b.s, 20, &f)) {
        /* Side edges sharp too: 24 rim corners of degree 3. */
        expect("prism at 20", &f, 36, 24, 36, 0, 14);
        vc_features_free(&f);
    }
    if (detect("prism at 160", &b.s, 160, &f)) {
        expect("prism at 160", &f, 0, 0, 0, 0, 1);
        vc_features_free(&f);
    }
    vc_surface_free(&b.s);

    /* A hexagonal prism at 50 degrees: sides differ by 60 degrees (sharp),
     * rims turn by 60 degrees (corners by degree anyway). At 70 degrees:
     * rims turn by 60 < 70 so the rims are closed creases. */
    builder h = {0};
    make_prism(&h, 6, 1);
    if (detect("hexagonal prism at 50", &h.s, 50, &f)) {
        expect("hexagonal prism at 50", &f, 18, 12, 18, 0, 8);
        vc_features_free(&f);
    }
    if (detect("hexagonal prism at 70", &h.s, 70, &f)) {
        expect("hexagonal prism at 70", &f, 12, 0, 2, 2, 3);
        vc_features_free(&f);
    }
    vc_surface_free(&h.s);
    builder p3 = {0};
    make_prism(&p3, 3, 1);
    if (detect("triangular prism at 130", &p3.s, 130, &f)) {
        /* Sides differ by 120 and caps by 90 degrees, both below 130:
         * nothing is sharp, and no sector spreads 130 degrees. */
        expect("triangular prism at 130", &f, 0, 0, 0, 0, 1);
        vc_features_free(&f);
    }
    if (detect("triangular prism at 110", &p3.s, 110, &f)) {
        /* Only the 3 side edges (120 > 110) are sharp: 3 creases that end
         * in the smooth caps, so 6 crease-end corners (also sector
         * corners: the two sides at a rim vertex differ by 120), and one
         * patch (the sides connect through the caps). */
        expect("triangular prism at 110", &f, 3, 6, 3, 0, 1);
        for (int64_t v = 0; v < 6; v++)
            CHECKF(f.vertex_corner[v] == (VC_CORNER_END | VC_CORNER_SECTOR), "triangular prism: vertex %lld why %d",
                  (long long)v, f.vertex_corner[v]);
        vc_features_free(&f);
    }
    if (detect("triangular prism at 80", &p3.s, 80, &f)) {
        expect("triangular prism at 80", &f, 9, 6, 9, 0, 5);
        vc_features_free(&f);
    }
    vc_surface_free(&p3.s);
}

static void test_turn_and_sector(void)
{
    /* A unit box: face normals differ by 90 degrees. At 100 degrees no
     * edge is sharp and no vertex sector spreads 100 degrees; at 80 the 12
     * box edges are sharp. */
    builder b = {0};
    for (int i = 0; i < 8; i++)
        add_v(&b, i & 1, i >> 1 & 1, i >> 2 & 1);
    static const int q[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (int k = 0; k < 6; k++)
        add_q(&b, q[k][0], q[k][1], q[k][2], q[k][3]);
    vc_features f;
    if (detect("box at 100", &b.s, 100, &f)) {
        expect("box at 100", &f, 0, 0, 0, 0, 1);
        vc_features_free(&f);
    }
    if (detect("box at 80", &b.s, 80, &f)) {
        expect("box at 80", &f, 12, 8, 12, 0, 6);
        vc_features_free(&f);
    }
    /* Flip one triangle: the angle test and the patch orientation see
     * through it; the flipped triangle is the one reoriented. */
    int64_t *t = b.s.tri + 3 * 5, tmp = t[1];
    t[1] = t[2];
    t[2] = tmp;
    if (detect("box with a flipped triangle", &b.s, 80, &f)) {
        expect("box with a flipped triangle", &f, 12, 8, 12, 0, 6);
        for (int64_t k = 0; k < b.s.n_triangles; k++)
            CHECKF(f.tri_orient[k] == (k == 5 ? -1 : 1), "flipped box: triangle %lld orient %d", (long long)k,
                  f.tri_orient[k]);
        vc_features_free(&f);
    }
    if (detect("box with a flipped triangle at 100", &b.s, 100, &f)) {
        expect("box with a flipped triangle at 100", &f, 0, 0, 0, 0, 1);
        CHECKF(f.tri_orient[5] == -1, "flipped box at 100: orient %d", f.tri_orient[5]);
        vc_features_free(&f);
    }
    vc_surface_free(&b.s);

    /* A cone apex: 8 sides around a vertex, neighbours differ by less than
     * theta, opposite ones by more: a sector corner with no sharp edge.
     * Closed by a fanned base. Side normals make 45 degrees with the
     * axis, so opposite sides differ by 90 degrees and neighbours by
     * about 29.6. */
    builder c = {0};
    int64_t apex = add_v(&c, 0, 0, 1), centre = add_v(&c, 0, 0, 0);
    for (int i = 0; i < 8; i++)
        add_v(&c, cos(2 * M_PI * i / 8), sin(2 * M_PI * i / 8), 0);
    for (int i = 0; i < 8; i++) {
        add_t(&c, apex, 2 + i, 2 + (i + 1) % 8);
        add_t(&c, centre, 2 + (i + 1) % 8, 2 + i);
    }
    if (detect("cone at 60", &c.s, 60, &f)) {
        /* Rim edges: normals differ by 135 (sharp); the rim is a closed
         * crease (turns by 45 < 60; the side sectors span less than 60). */
        expect("cone at 60", &f, 8, 1, 1, 1, 2);
        CHECKF(f.vertex_corner[apex] == VC_CORNER_SECTOR, "cone: apex corner %d", f.vertex_corner[apex]);
        vc_features_free(&f);
    }
    vc_surface_free(&c.s);
}

static void test_open_and_moebius(void)
{
    /* An open square made of two triangles: 4 boundary edges, 4 corners
     * (two boundary edges at 90 degrees), 4 creases, 1 patch. */
    builder b = {0};
    add_v(&b, 0, 0, 0);
    add_v(&b, 1, 0, 0);
    add_v(&b, 1, 1, 0);
    add_v(&b, 0, 1, 0);
    add_q(&b, 0, 1, 2, 3);
    vc_features f;
    if (detect("square", &b.s, 60, &f)) {
        expect("square", &f, 4, 4, 4, 0, 1);
        CHECKF(f.n_boundary_edges == 4, "square: boundary edges %lld", (long long)f.n_boundary_edges);
        vc_features_free(&f);
    }
    vc_surface_free(&b.s);

    /* A Moebius strip: one non-orientable patch; its boundary is a single
     * closed crease of 2n edges. */
    builder m = {0};
    const int n = 40;
    for (int i = 0; i < n; i++) {
        double u = 2 * M_PI * i / n;
        for (int s = -1; s <= 1; s += 2) {
            double r = 3 + 0.5 * s * cos(u / 2);
            add_v(&m, r * cos(u), r * sin(u), 0.5 * s * sin(u / 2));
        }
    }
    for (int i = 0; i < n; i++) {
        int64_t a0 = 2 * i, a1 = 2 * i + 1, b0, b1;
        if (i + 1 < n) {
            b0 = 2 * (i + 1);
            b1 = b0 + 1;
        } else { /* the twist: s = -1 meets s = +1 */
            b0 = 1;
            b1 = 0;
        }
        add_q(&m, a0, b0, b1, a1);
    }
    if (detect("moebius", &m.s, 60, &f)) {
        expect("moebius", &f, 2 * n, 0, 1, 1, 1);
        CHECKF(f.n_nonorientable_patches == 1 && !f.patch_orientable[0], "moebius: orientable");
        vc_features_free(&f);
    }
    vc_surface_free(&m.s);
}

static void test_bad_input(void)
{
    builder b = {0};
    add_v(&b, 0, 0, 0);
    add_v(&b, 1, 0, 0);
    add_v(&b, 0, 1, 0);
    add_t(&b, 0, 1, 2);
    vc_features f;
    vc_error err = {0, ""};
    const double bad[] = {0, -5, 180, 200, NAN};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        int rc = vc_features_detect(&b.s, bad[i], &f, &err);
        CHECKF(rc == VC_EPARAM && strstr(err.msg, "sharp angle") && f.edge_vertex == NULL, "angle %g: rc %d %s",
              bad[i], rc, err.msg);
    }
    b.s.tri[2] = 7;
    CHECKF(vc_features_detect(&b.s, 60, &f, &err) == VC_EINPUT && strstr(err.msg, "vertex 8"), "bad index: %s",
          err.msg);
    b.s.tri[2] = 1;
    CHECKF(vc_features_detect(&b.s, 60, &f, &err) == VC_EINPUT && strstr(err.msg, "repeats"), "repeat: %s",
          err.msg);
    b.s.tri[2] = 2;
    /* A single triangle: three boundary edges, three corners (turn). */
    if (detect("triangle", &b.s, 60, &f)) {
        expect("triangle", &f, 3, 3, 3, 0, 1);
        vc_features_free(&f);
    }
    /* A zero-area triangle (0, 1, 3 on the x axis) sharing the edge 0-1
     * with a real one: that edge is not sharp by angle; the four other
     * edges are boundary edges. Corners at 0 (90 degrees), 2 (45) and 3
     * (0); vertex 1 (135 degrees, one sector) is not one, so 2-1-3 is one
     * crease. */
    add_v(&b, 2, 0, 0);
    add_t(&b, 1, 0, 3);
    if (detect("zero-area triangle", &b.s, 60, &f)) {
        expect("zero-area triangle", &f, 4, 3, 3, 0, 1);
        CHECKF(f.n_degenerate == 1 && f.vertex_corner[1] == 0 && f.edge_sharp[vc_features_find_edge(&f, 0, 1)] == 0,
              "zero-area triangle: %lld degenerate, corner %d", (long long)f.n_degenerate, f.vertex_corner[1]);
        vc_features_free(&f);
    }
    vc_features_free(&f); /* twice: safe on a zeroed struct */
    vc_surface_free(&b.s);
}

/* A box [0,1]^2 x [0,0.3] whose top is a 100 x 100 grid (the other faces
 * fans to the bottom corners), the top's middle (grid lines 30 to 70)
 * moved up and down by seeded noise of +-amp: folds over 60 degrees there
 * (slopes up to 2 amp / 0.01), and the box's own 90-degree edges. */
enum { TRAY_N = 100 };
static void make_noisy_tray(builder *b, double amp)
{
    const int n = TRAY_N;
    const double h = 0.3;
    uint64_t state = 12345;
    for (int j = 0; j <= n; j++)
        for (int i = 0; i <= n; i++) {
            double z = h;
            if (i >= 30 && i <= 70 && j >= 30 && j <= 70) {
                state = state * 6364136223846793005ULL + 1442695040888963407ULL;
                z += amp * (2.0 * (double)(state >> 11) / 9007199254740992.0 - 1.0);
            }
            add_v(b, (double)i / n, (double)j / n, z);
        }
#define T(i, j) ((int64_t)(j) * (n + 1) + (i))
    for (int j = 0; j < n; j++)
        for (int i = 0; i < n; i++)
            add_q(b, T(i, j), T(i + 1, j), T(i + 1, j + 1), T(i, j + 1));
    const int64_t b00 = add_v(b, 0, 0, 0), b10 = add_v(b, 1, 0, 0), b11 = add_v(b, 1, 1, 0),
                  b01 = add_v(b, 0, 1, 0);
    add_q(b, b00, b01, b11, b10);
    /* each side: a fan from its first bottom corner over the loop (first
     * corner, second corner, the top row back), counter-clockwise seen
     * from outside */
    int64_t loop[TRAY_N + 3];
    for (int side = 0; side < 4; side++) {
        int m = 0;
        const int64_t c0 = side == 0 ? b00 : side == 1 ? b10 : side == 2 ? b11 : b01;
        const int64_t c1 = side == 0 ? b10 : side == 1 ? b11 : side == 2 ? b01 : b00;
        loop[m++] = c0;
        loop[m++] = c1;
        for (int k = n; k >= 0; k--)
            loop[m++] = side == 0 ? T(k, 0) : side == 1 ? T(n, k) : side == 2 ? T(n - k, n) : T(0, n - k);
        for (int k = 1; k + 1 < m; k++)
            add_t(b, loop[0], loop[k], loop[k + 1]);
    }
#undef T
}

static void test_noise_at_scale(void)
{
    builder b = {0};
    make_noisy_tray(&b, 0.006);
    const int n = TRAY_N;
    vc_features raw, at;
    vc_error err;
    CHECK(vc_features_detect(&b.s, 60, &raw, &err) == 0);
    CHECK(vc_features_detect_scaled(&b.s, 60, NULL, 0.03, &at, &err) == 0);
    check_invariants("noisy tray at 0.03", &b.s, &at);
    /* the top's inside edges: sharp by angle in the raw features, none at
     * the scale; the rims (4 n + 4 edges at 90 degrees) sharp in both */
    int64_t inside_raw = 0, inside_at = 0, rim_at = 0;
    for (int64_t e = 0; e < raw.n_edges; e++) {
        const int64_t u = raw.edge_vertex[2 * e], v = raw.edge_vertex[2 * e + 1];
        const int in = u < (n + 1) * (n + 1) && v < (n + 1) * (n + 1) && u % (n + 1) != 0 &&
                       u % (n + 1) != n && v % (n + 1) != 0 && v % (n + 1) != n && u / (n + 1) != 0 &&
                       u / (n + 1) != n && v / (n + 1) != 0 && v / (n + 1) != n;
        inside_raw += in && raw.edge_sharp[e];
        inside_at += in && at.edge_sharp[e];
        rim_at += !in && at.edge_sharp[e];
    }
    CHECKF(inside_raw > 20, "noisy tray: %lld folds over 60 degrees (the test needs them)", (long long)inside_raw);
    CHECKF(inside_at == 0 && at.n_sharp_noise == inside_raw, "noisy tray: %lld sharp inside at the scale, %lld noise, of %lld",
           (long long)inside_at, (long long)at.n_sharp_noise, (long long)inside_raw);
    CHECKF(rim_at == 4 * n + 8 && at.n_corners == 8 && at.n_patches == 6,
           "noisy tray: %lld rim edges (want %d), %lld corners, %lld patches", (long long)rim_at, 4 * n + 8,
           (long long)at.n_corners, (long long)at.n_patches);
    /* the smoothed normals of the noisy middle point up, where the raw
     * ones swing by more than 60 degrees */
    CHECK(at.tri_smooth_normal != NULL);
    int64_t tilted_raw = 0, tilted_smooth = 0;
    for (int64_t t = 0; at.tri_smooth_normal && t < 2 * n * n; t++) {
        tilted_raw += at.tri_normal[3 * t + 2] < cos(30 * M_PI / 180);
        tilted_smooth += at.tri_smooth_normal[3 * t + 2] < cos(30 * M_PI / 180);
    }
    CHECKF(tilted_raw > 20 && tilted_smooth == 0, "noisy tray: %lld raw normals over 30 degrees from up, %lld smoothed",
           (long long)tilted_raw, (long long)tilted_smooth);
    vc_features_free(&at);
    /* the same at a scale too small for the noise: nothing judged noise */
    CHECK(vc_features_detect_scaled(&b.s, 60, NULL, 0.002, &at, &err) == 0);
    CHECKF(at.n_sharp_edges == raw.n_sharp_edges && at.n_sharp_noise == 0 && at.tri_smooth_normal == NULL,
           "noisy tray at 0.002: %lld sharp (raw %lld), %lld noise", (long long)at.n_sharp_edges,
           (long long)raw.n_sharp_edges, (long long)at.n_sharp_noise);
    vc_features_free(&at);
    vc_features_free(&raw);
    vc_surface_free(&b.s);
}

int main(void)
{
    const char *models = getenv("VC_MODELS");
    if (models && *models)
        test_models(models);
    else
        fprintf(stderr, "VC_MODELS not set: reference models skipped\n");
    test_tets_sharing_edge();
    test_pinch();
    test_prism();
    test_turn_and_sector();
    test_open_and_moebius();
    test_bad_input();
    test_noise_at_scale();
    if (failures) {
        fprintf(stderr, "test_features: %d failures\n", failures);
        return 1;
    }
    printf("test_features: all passed\n");
    return 0;
}
