/* Tests of the quality module (vorocrust/quality): known answers for
 * triangles, cubes and tetrahedra; the enclosing and inscribed balls of
 * random Voronoi cells against brute force; the inscribed-ball LP on
 * degenerate inputs; the Hausdorff distance; statistics. */
#include "vorocrust/quality.h"
#include "vorocrust/random.h"
#include "vorocrust/voronoi.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#ifdef _OPENMP
#include <omp.h>
#endif

#include "test_check.h"

static double dist(const double *a, const double *b)
{
    return sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                (a[2] - b[2]) * (a[2] - b[2]));
}

/* ---- a box cell --------------------------------------------------------- */

static const int64_t box_faces[24] = {0, 3, 2, 1, 4, 5, 6, 7, 0, 1, 5, 4,
                                      2, 3, 7, 6, 1, 2, 6, 5, 0, 4, 7, 3};

/* Box [0,sx]x[0,sy]x[0,sz]; vertex i has bits x=i&1^((i>>1)&1)... laid out
 * as the usual hexahedron: 0 (0,0,0) 1 (x,0,0) 2 (x,y,0) 3 (0,y,0), 4-7 the
 * same at z. Faces outward. */
static void box_points(double sx, double sy, double sz, double pts[24])
{
    static const int bits[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                                   {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
    for (int i = 0; i < 8; i++) {
        pts[3 * i] = bits[i][0] * sx;
        pts[3 * i + 1] = bits[i][1] * sy;
        pts[3 * i + 2] = bits[i][2] * sz;
    }
}

static void test_triangles(void)
{
    double a[3] = {0, 0, 0}, b[3] = {1, 0, 0}, c[3] = {0.5, sqrt(3.0) / 2, 0};
    CHECK_NEAR(vc_triangle_quality(a, b, c), 1.0, 1e-15);
    double ang[3];
    vc_triangle_angles(a, b, c, ang);
    for (int i = 0; i < 3; i++)
        CHECK_NEAR(ang[i], 60.0, 1e-12);
    /* right isosceles: S = 1/2, h = sqrt 2, P = (2 + sqrt 2) / 2 */
    double r[3] = {0, 1, 0};
    CHECK_NEAR(vc_triangle_quality(a, b, r), 3.0 / (sqrt(3.0) * sqrt(2.0) * (1 + sqrt(2.0) / 2)), 1e-15);
    vc_triangle_angles(a, b, r, ang);
    CHECK_NEAR(ang[0], 90.0, 1e-12);
    CHECK_NEAR(ang[1], 45.0, 1e-12);
    CHECK_NEAR(ang[2], 45.0, 1e-12);
    /* scale and rotation invariance, degenerate triangles */
    double a2[3] = {3, 4, 5}, b2[3] = {3, 4, 12}, c2[3] = {3, 4 + 7 * sqrt(3.0) / 2, 8.5};
    CHECK_NEAR(vc_triangle_quality(a2, b2, c2), 1.0, 1e-14);
    double col[3] = {2, 0, 0};
    CHECK_NEAR(vc_triangle_quality(a, b, col), 0.0, 0);
    CHECK_NEAR(vc_triangle_quality(a, a, a), 0.0, 0);
    vc_triangle_angles(a, a, b, ang);
    CHECK(ang[0] == 0 && ang[1] == 0 && ang[2] == 0);
    vc_triangle_angles(a, b, col, ang); /* flat: 0, 180, 0 */
    CHECK_NEAR(ang[0] + ang[1] + ang[2], 180.0, 1e-12);

    /* point-triangle distance: every region, and against dense sampling */
    CHECK_NEAR(vc_point_triangle_distance((double[3]){0.2, 0.2, 0.7}, a, b, r), 0.7, 1e-15);
    CHECK_NEAR(vc_point_triangle_distance((double[3]){-1, -1, 0}, a, b, r), sqrt(2.0), 1e-15);
    CHECK_NEAR(vc_point_triangle_distance((double[3]){0.5, -2, 0}, a, b, r), 2.0, 1e-15);
    CHECK_NEAR(vc_point_triangle_distance((double[3]){1, 1, 0}, a, b, r), sqrt(0.5), 1e-15);
    CHECK_NEAR(vc_point_triangle_distance((double[3]){1, 1, 1}, a, a, a), sqrt(3.0), 1e-15);
    vc_rng rng;
    vc_rng_init(&rng, 7, 0);
    for (int k = 0; k < 200; k++) {
        double t[3][3], p[3];
        for (int i = 0; i < 3; i++)
            for (int d = 0; d < 3; d++)
                t[i][d] = vc_rng_uniform(&rng);
        for (int d = 0; d < 3; d++)
            p[d] = 3 * vc_rng_uniform(&rng) - 1;
        double exact = vc_point_triangle_distance(p, t[0], t[1], t[2]);
        double sampled = INFINITY;
        int n = 60;
        for (int i = 0; i <= n; i++)
            for (int j = 0; i + j <= n; j++) {
                double q[3];
                for (int d = 0; d < 3; d++)
                    q[d] = t[0][d] + (double)i / n * (t[1][d] - t[0][d]) +
                           (double)j / n * (t[2][d] - t[0][d]);
                sampled = fmin(sampled, dist(p, q));
            }
        CHECK(exact <= sampled + 1e-12);
        CHECK(exact >= sampled - 0.03); /* sample spacing < sqrt(3)/60 */
    }
}

static void check_cube(const double pts[24], const int64_t *faces, int64_t nf,
                       const int64_t *offsets, double side)
{
    vc_cell cell = {pts, 0, NULL, nf, offsets, faces};
    vc_cell_measures m;
    CHECK(vc_cell_measure(&cell, &m) == 0);
    CHECK_NEAR(m.volume, side * side * side, 1e-14);
    for (int d = 0; d < 3; d++) {
        CHECK_NEAR(m.centroid[d], side / 2, 1e-14);
        CHECK_NEAR(m.enclosing.center[d], side / 2, 1e-14);
        CHECK_NEAR(m.inscribed.center[d], side / 2, 1e-12);
    }
    CHECK_NEAR(m.enclosing.radius, side * sqrt(3.0) / 2, 1e-14);
    CHECK_NEAR(m.inscribed.radius, side / 2, 1e-12);
    CHECK_NEAR(m.fatness, sqrt(3.0), 1e-12);
    CHECK_NEAR(m.shortest_edge, side, 1e-14);
    CHECK_NEAR(m.shortest_edge_rel, 2 / sqrt(3.0), 1e-12);
}

static void test_cube_and_lp_degenerate(void)
{
    double pts[24];
    int64_t offsets[8];
    for (int f = 0; f <= 6; f++)
        offsets[f] = 4 * f;
    box_points(1, 1, 1, pts);
    check_cube(pts, box_faces, 6, offsets, 1);
    int64_t ids[8] = {0, 1, 2, 3, 4, 5, 6, 7};
    vc_cell with_ids = {pts, 8, ids, 6, offsets, box_faces};
    vc_cell_measures m;
    CHECK(vc_cell_measure(&with_ids, &m) == 0);
    CHECK_NEAR(m.fatness, sqrt(3.0), 1e-12);

    /* inward faces: same answers, negative signed volume */
    int64_t inward[24];
    for (int f = 0; f < 6; f++)
        for (int k = 0; k < 4; k++)
            inward[4 * f + k] = box_faces[4 * f + 3 - k];
    CHECK_NEAR(vc_cell_volume(&(vc_cell){pts, 0, NULL, 6, offsets, inward}, NULL), -1.0, 1e-14);
    check_cube(pts, inward, 6, offsets, 1);

    /* every face listed twice (parallel duplicate constraints) */
    int64_t twice[48], off12[13];
    for (int f = 0; f < 12; f++) {
        off12[f] = 4 * f;
        for (int k = 0; k < 4; k++)
            twice[4 * f + k] = box_faces[4 * (f % 6) + k];
    }
    off12[12] = 48;
    vc_cell dup = {pts, 0, NULL, 12, off12, twice};
    vc_ball in;
    CHECK(vc_max_inscribed_ball(&dup, &in) == 0);
    CHECK_NEAR(in.radius, 0.5, 1e-12);

    /* a box 2 x 1 x 1: the inscribed centre is not unique (any x in [0.5,
     * 1.5]); the radius is, and the ball must fit */
    box_points(2, 1, 1, pts);
    vc_cell slab = {pts, 0, NULL, 6, offsets, box_faces};
    CHECK(vc_max_inscribed_ball(&slab, &in) == 0);
    CHECK_NEAR(in.radius, 0.5, 1e-12);
    CHECK(in.center[0] >= 0.5 - 1e-12 && in.center[0] <= 1.5 + 1e-12);
    CHECK_NEAR(in.center[1], 0.5, 1e-12);
    CHECK_NEAR(in.center[2], 0.5, 1e-12);

    /* a very thin box: radius half the thickness, fatness huge */
    box_points(1, 1, 1e-9, pts);
    CHECK(vc_cell_measure(&slab, &m) == 0);
    CHECK_NEAR(m.inscribed.radius, 0.5e-9, 1e-20);
    CHECK(m.fatness > 1e8);

    /* one face missing: a half-infinite square prism, radius still 1/2 */
    box_points(1, 1, 1, pts);
    vc_cell prism = {pts, 0, NULL, 5, offsets, box_faces};
    CHECK(vc_max_inscribed_ball(&prism, &in) == 0);
    CHECK_NEAR(in.radius, 0.5, 1e-12);
    /* only the -x, -y, -z faces (one twice): balls of any size fit */
    int64_t corner_faces[16];
    const int pickf[4] = {0, 2, 5, 0};
    for (int f = 0; f < 4; f++)
        for (int k = 0; k < 4; k++)
            corner_faces[4 * f + k] = box_faces[4 * pickf[f] + k];
    vc_cell open = {pts, 0, NULL, 4, offsets, corner_faces};
    CHECK(vc_max_inscribed_ball(&open, &in) == VC_EINPUT);
    /* fewer than 4 faces */
    vc_cell three = {pts, 0, NULL, 3, offsets, box_faces};
    CHECK(vc_max_inscribed_ball(&three, &in) == VC_EINPUT);

    /* zero-area faces (a repeated vertex cycle of 3 equal ids) are ignored */
    int64_t with_zero[27], off7[8];
    memcpy(with_zero, box_faces, sizeof box_faces);
    with_zero[24] = with_zero[25] = with_zero[26] = 6;
    for (int f = 0; f < 7; f++)
        off7[f] = 4 * f;
    off7[7] = 27;
    vc_cell zero = {pts, 0, NULL, 7, off7, with_zero};
    CHECK(vc_max_inscribed_ball(&zero, &in) == 0);
    CHECK_NEAR(in.radius, 0.5, 1e-12);

    /* far from the origin: relative accuracy is kept */
    for (int i = 0; i < 8; i++) {
        pts[3 * i] += 1e6;
        pts[3 * i + 1] -= 3e5;
    }
    vc_cell far = {pts, 0, NULL, 6, offsets, box_faces};
    CHECK(vc_cell_measure(&far, &m) == 0);
    CHECK_NEAR(m.fatness, sqrt(3.0), 1e-8);
    CHECK_NEAR(m.volume, 1.0, 1e-8);
}

/* A cell of a gyroid lattice's mesh (session 41) on which the tableau's
 * phase 1 stopped 4e-6 short of feasibility (faces of 5e-9 to 1.4e-5 in
 * area): "some cells could not be measured". The enumeration behind it
 * finds the ball. */
static void test_lp_fallback(void)
{
    static const double pts[] = {
        -0.98461400828937384, 0.17911966121800224, 0.87351472084810144,
        -0.98394209058503745, 0.17872380052742678, 0.87618391013814911,
        -0.98461305334096083, 0.17924821806183547, 0.87352121182299836,
        -0.98256067559123039, 0.18050992861390114, 0.87225996078725876,
        -0.9827719965342735, 0.18050992861390114, 0.87239602756694867,
        -0.98234096917986424, 0.18072963502526729, 0.87236888484684283,
        -0.98125021513353783, 0.18110490805141838, 0.87286438078650985,
        -0.98459486290812492, 0.1792667706719229, 0.87349109309310591,
        -0.97993850459007681, 0.18120035600374454, 0.8745711859947396,
        -0.98059464791794515, 0.18101609809748712, 0.87314229548136946,
        -0.98459486290812492, 0.17911226173225728, 0.87348131736381773,
        -0.98256067559123039, 0.17824862874596334, 0.8721168890957679,
        -0.98079537950625095, 0.17743195139538437, 0.87282871103777049,
        -0.98000203841716993, 0.17697939635238885, 0.87556154174065093,
        -0.98056504123132149, 0.17843432261799019, 0.87299175233476056,
        -0.98032595971442382, 0.18070733506853842, 0.87323896814365676,
        -0.98033208779241121, 0.18073247830548822, 0.87323790854622763,
    };
    static const int64_t fv[] = {0, 1, 2, 3, 4, 5, 6, 5, 4, 7, 2, 1, 8, 9, 6, 8, 10, 0, 2, 7, 4, 3, 11, 10, 7, 12, 13, 1, 0, 10, 11, 8, 13, 14, 15, 8, 16, 9, 11, 3, 5, 6, 9, 16, 15, 14, 12, 12, 14, 13, 15, 16, 8, 13, 8, 1};
    static const int64_t off[] = {0, 3, 6, 13, 16, 20, 25, 31, 35, 38, 47, 50, 53, 56};
    const vc_cell cell = {pts, 0, NULL, 13, off, fv};
    vc_cell_measures m;
    CHECK(vc_cell_measure(&cell, &m) == 0);
    CHECK(isfinite(m.fatness) && m.fatness > 1 && m.fatness < 3);
    /* the ball lies inside: at least its radius behind every face plane,
     * and no smaller than the ball at the centroid that touches the
     * nearest plane */
    double at_centroid = INFINITY;
    for (int f = 0; f < 13; f++) {
        const double *a = pts + 3 * fv[off[f]], *b = pts + 3 * fv[off[f] + 1], *c = pts + 3 * fv[off[f] + 2];
        double u[3], v[3], n[3];
        for (int d = 0; d < 3; d++) {
            u[d] = b[d] - a[d];
            v[d] = c[d] - a[d];
        }
        n[0] = u[1] * v[2] - u[2] * v[1];
        n[1] = u[2] * v[0] - u[0] * v[2];
        n[2] = u[0] * v[1] - u[1] * v[0];
        const double l = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        double behind = 0, behind_c = 0;
        for (int d = 0; d < 3; d++) {
            behind += (a[d] - m.inscribed.center[d]) * n[d] / l;
            behind_c += (a[d] - m.centroid[d]) * n[d] / l;
        }
        CHECK(behind >= m.inscribed.radius * (1 - 1e-9));
        at_centroid = fmin(at_centroid, behind_c);
    }
    CHECK(m.inscribed.radius >= at_centroid);
}

static void test_tetrahedra(void)
{
    /* regular tetrahedron: fatness R / r = 3, dihedral acos(1/3) */
    double reg[4][3] = {{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}};
    double pts[12], fvx[12];
    int64_t ids[4], off[5], fv[12];
    (void)fvx;
    vc_cell cell;
    vc_tetra_cell(reg, pts, ids, off, fv, &cell);
    vc_cell_measures m;
    CHECK(vc_cell_measure(&cell, &m) == 0);
    CHECK(vc_cell_volume(&cell, NULL) > 0);
    CHECK_NEAR(m.volume, 8.0 / 3.0, 1e-14);
    CHECK_NEAR(m.enclosing.radius, sqrt(3.0), 1e-14);
    CHECK_NEAR(m.inscribed.radius, sqrt(3.0) / 3, 1e-12);
    CHECK_NEAR(m.fatness, 3.0, 1e-12);
    for (int d = 0; d < 3; d++) {
        CHECK_NEAR(m.centroid[d], 0, 1e-15);
        CHECK_NEAR(m.inscribed.center[d], 0, 1e-12);
    }
    double deg[6], lo, hi;
    vc_tetra_dihedral_angles(reg, deg, &lo, &hi);
    for (int k = 0; k < 6; k++)
        CHECK_NEAR(deg[k], acos(1.0 / 3.0) * 180 / 3.14159265358979323846, 1e-12);
    /* reversed vertex order: same measures (faces made outward) */
    double rev[4][3];
    memcpy(rev[0], reg[1], sizeof rev[0]);
    memcpy(rev[1], reg[0], sizeof rev[0]);
    memcpy(rev[2], reg[2], sizeof rev[0]);
    memcpy(rev[3], reg[3], sizeof rev[0]);
    vc_tetra_cell(rev, pts, ids, off, fv, &cell);
    CHECK(vc_cell_volume(&cell, NULL) > 0);
    CHECK(vc_cell_measure(&cell, &m) == 0);
    CHECK_NEAR(m.fatness, 3.0, 1e-12);

    /* corner tetrahedron: dihedral angles 90 at the three edges from the
     * origin, acos(1/sqrt 3) at the three slanted edges */
    double corner[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    vc_tetra_dihedral_angles(corner, deg, &lo, &hi);
    CHECK_NEAR(deg[0], 90, 1e-12);
    CHECK_NEAR(deg[1], 90, 1e-12);
    CHECK_NEAR(deg[2], 90, 1e-12);
    CHECK_NEAR(deg[3], acos(1 / sqrt(3.0)) * 180 / 3.14159265358979323846, 1e-12);
    CHECK_NEAR(lo, acos(1 / sqrt(3.0)) * 180 / 3.14159265358979323846, 1e-12);
    CHECK_NEAR(hi, 90, 1e-12);
    vc_tetra_cell(corner, pts, ids, off, fv, &cell);
    CHECK(vc_cell_measure(&cell, &m) == 0);
    CHECK_NEAR(m.volume, 1.0 / 6.0, 1e-15);
    CHECK_NEAR(m.inscribed.radius, 1.0 / (3 + sqrt(3.0)), 1e-12);

    /* flattening a tetrahedron: the fatness grows without bound */
    double prev = 0;
    for (int k = 1; k <= 6; k++) {
        double h = pow(10.0, -k);
        double flat[4][3] = {{1, 1, h}, {1, -1, -h}, {-1, 1, -h}, {-1, -1, h}};
        vc_tetra_cell(flat, pts, ids, off, fv, &cell);
        CHECK(vc_cell_measure(&cell, &m) == 0);
        CHECK(m.fatness > prev * 5);
        CHECK(m.fatness > 1.0 / h); /* R ~ sqrt 2, r ~ 3 V / area ~ h */
        vc_tetra_dihedral_angles(flat, deg, &lo, &hi);
        CHECK(lo < 10 * h * 180 / 3.14159 && hi > 180 - 10 * h * 180 / 3.14159);
        prev = m.fatness;
    }
}

/* ---- random Voronoi cells against brute force ----------------------------- */

/* Smallest ball over all subsets of 2..4 points that contains them all:
 * the definition of the minimum enclosing ball, at O(n^5). */
static double brute_enclosing_radius(int n, const double *p)
{
    double best = INFINITY;
    int idx[4];
    for (int k = 2; k <= 4; k++) {
        for (idx[0] = 0; idx[0] < n; idx[0]++)
            for (idx[1] = idx[0] + 1; idx[1] < n; idx[1]++)
                for (idx[2] = k > 2 ? idx[1] + 1 : n - 1; idx[2] < n; idx[2]++)
                    for (idx[3] = k > 3 ? idx[2] + 1 : n - 1; idx[3] < n; idx[3]++) {
                        /* circumcentre of the k points in their affine hull */
                        const double *q0 = p + 3 * idx[0];
                        double v[3][3], g[3][3], r[3], l[3];
                        int m = k - 1;
                        for (int i = 0; i < m; i++)
                            for (int d = 0; d < 3; d++)
                                v[i][d] = p[3 * idx[i + 1] + d] - q0[d];
                        for (int i = 0; i < m; i++) {
                            for (int j = 0; j < m; j++)
                                g[i][j] = 2 * (v[i][0] * v[j][0] + v[i][1] * v[j][1] + v[i][2] * v[j][2]);
                            r[i] = 0.5 * g[i][i];
                        }
                        /* Cramer / elimination without pivoting: fine for
                         * random points, singular subsets are skipped */
                        int ok = 1;
                        for (int c = 0; c < m && ok; c++) {
                            if (fabs(g[c][c]) < 1e-14) {
                                ok = 0;
                                break;
                            }
                            for (int i = c + 1; i < m; i++) {
                                double f = g[i][c] / g[c][c];
                                for (int j = c; j < m; j++)
                                    g[i][j] -= f * g[c][j];
                                r[i] -= f * r[c];
                            }
                        }
                        if (!ok)
                            continue;
                        for (int i = m - 1; i >= 0; i--) {
                            double s = r[i];
                            for (int j = i + 1; j < m; j++)
                                s -= g[i][j] * l[j];
                            l[i] = s / g[i][i];
                        }
                        double c[3];
                        for (int d = 0; d < 3; d++) {
                            c[d] = q0[d];
                            for (int j = 0; j < m; j++)
                                c[d] += l[j] * v[j][d];
                        }
                        double rad = dist(c, q0);
                        if (rad >= best)
                            continue;
                        int all = 1;
                        for (int i = 0; i < n && all; i++)
                            all = dist(c, p + 3 * i) <= rad * (1 + 1e-10);
                        if (all)
                            best = rad;
                    }
    }
    return best;
}

/* Face planes (unit outward normal, offset) of an outward cell. */
static int cell_planes(const vc_cell *cell, double (*pl)[4])
{
    int m = 0;
    for (int64_t f = 0; f < cell->n_faces; f++) {
        int64_t b = cell->face_offsets[f], e = cell->face_offsets[f + 1];
        double n[3] = {0, 0, 0};
        const double *p0 = cell->points + 3 * cell->face_vertices[b];
        for (int64_t k = b + 1; k + 1 < e; k++) {
            const double *p1 = cell->points + 3 * cell->face_vertices[k];
            const double *p2 = cell->points + 3 * cell->face_vertices[k + 1];
            double u[3] = {p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]};
            double w[3] = {p2[0] - p0[0], p2[1] - p0[1], p2[2] - p0[2]};
            n[0] += u[1] * w[2] - u[2] * w[1];
            n[1] += u[2] * w[0] - u[0] * w[2];
            n[2] += u[0] * w[1] - u[1] * w[0];
        }
        double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        if (len < 1e-14)
            continue;
        for (int d = 0; d < 3; d++)
            pl[m][d] = n[d] / len;
        pl[m][3] = pl[m][0] * p0[0] + pl[m][1] * p0[1] + pl[m][2] * p0[2];
        m++;
    }
    return m;
}

/* Largest r over every vertex of the LP (4 tight planes): brute force. */
static double brute_inscribed_radius(int m, double (*pl)[4])
{
    double best = -INFINITY;
    int i[4];
    for (i[0] = 0; i[0] < m; i[0]++)
        for (i[1] = i[0] + 1; i[1] < m; i[1]++)
            for (i[2] = i[1] + 1; i[2] < m; i[2]++)
                for (i[3] = i[2] + 1; i[3] < m; i[3]++) {
                    double a[4][5];
                    for (int r = 0; r < 4; r++) {
                        for (int d = 0; d < 3; d++)
                            a[r][d] = pl[i[r]][d];
                        a[r][3] = 1;
                        a[r][4] = pl[i[r]][3];
                    }
                    int ok = 1;
                    for (int c = 0; c < 4 && ok; c++) {
                        int piv = c;
                        for (int r = c + 1; r < 4; r++)
                            if (fabs(a[r][c]) > fabs(a[piv][c]))
                                piv = r;
                        if (fabs(a[piv][c]) < 1e-10) {
                            ok = 0;
                            break;
                        }
                        for (int j = 0; j < 5; j++) {
                            double t = a[c][j];
                            a[c][j] = a[piv][j];
                            a[piv][j] = t;
                        }
                        for (int r = 0; r < 4; r++)
                            if (r != c) {
                                double f = a[r][c] / a[c][c];
                                for (int j = c; j < 5; j++)
                                    a[r][j] -= f * a[c][j];
                            }
                    }
                    if (!ok)
                        continue;
                    double x[4];
                    for (int r = 0; r < 4; r++)
                        x[r] = a[r][4] / a[r][r];
                    int feasible = 1;
                    for (int f = 0; f < m && feasible; f++)
                        feasible = pl[f][0] * x[0] + pl[f][1] * x[1] + pl[f][2] * x[2] + x[3] <=
                                   pl[f][3] + 1e-9;
                    if (feasible && x[3] > best)
                        best = x[3];
                }
    return best;
}

static void test_random_cells(void)
{
    vc_seeds seeds;
    vc_error err;
    int n = 60;
    CHECK(vc_seeds_alloc(&seeds, n, &err) == 0);
    vc_rng rng;
    vc_rng_init(&rng, 12345, 0);
    for (int i = 0; i < 3 * n; i++)
        seeds.xyz[i] = vc_rng_uniform(&rng);
    vc_voronoi_options opt;
    vc_voronoi_options_default(&opt);
    opt.has_box = 1;
    opt.box[0] = opt.box[1] = opt.box[2] = 0;
    opt.box[3] = opt.box[4] = opt.box[5] = 1;
    vc_polymesh mesh;
    memset(&mesh, 0, sizeof mesh);
    CHECK(vc_voronoi_build(&seeds, &opt, &mesh, &err) == 0);
    double total = 0;
    int checked = 0;
    for (int64_t c = 0; c < mesh.n_cells; c++) {
        /* the cell's faces, outward, with the points copied locally */
        int64_t nf = mesh.cell_offsets[c + 1] - mesh.cell_offsets[c];
        int64_t *off = malloc(sizeof *off * (size_t)(nf + 1));
        int64_t len = 0;
        for (int64_t k = 0; k < nf; k++)
            len += vc_polymesh_face_size(&mesh, mesh.cell_faces[mesh.cell_offsets[c] + k]);
        int64_t *fv = malloc(sizeof *fv * (size_t)len);
        double *pts = malloc(sizeof *pts * 3 * (size_t)len);
        int64_t *vid = malloc(sizeof *vid * (size_t)len);
        int64_t nv = 0, at = 0;
        off[0] = 0;
        for (int64_t k = 0; k < nf; k++) {
            int64_t f = mesh.cell_faces[mesh.cell_offsets[c] + k];
            int64_t b = mesh.face_offsets[f], e = mesh.face_offsets[f + 1];
            int own = mesh.face_owner[f] == c;
            for (int64_t i = 0; i < e - b; i++) {
                int64_t g = mesh.face_vertices[own ? b + i : e - 1 - i];
                int64_t loc = -1;
                for (int64_t j = 0; j < nv; j++)
                    if (vid[j] == g)
                        loc = j;
                if (loc < 0) {
                    loc = nv;
                    vid[nv] = g;
                    memcpy(pts + 3 * nv, mesh.points + 3 * g, 3 * sizeof(double));
                    nv++;
                }
                fv[at++] = loc;
            }
            off[k + 1] = at;
        }
        vc_cell cell = {pts, 0, NULL, nf, off, fv};
        vc_cell_measures m;
        CHECK(vc_cell_measure(&cell, &m) == 0);
        total += m.volume;
        CHECK_NEAR(m.volume, mesh.cell_volume[c], 1e-12);
        /* enclosing: every vertex inside, >= 2 on the sphere, minimal */
        int touching = 0;
        for (int64_t j = 0; j < nv; j++) {
            double dj = dist(pts + 3 * j, m.enclosing.center);
            CHECK(dj <= m.enclosing.radius * (1 + 1e-12));
            touching += dj >= m.enclosing.radius * (1 - 1e-9);
        }
        CHECK(touching >= 2);
        CHECK_NEAR(m.enclosing.radius, brute_enclosing_radius((int)nv, pts), 1e-9);
        /* inscribed: inside every face plane, touching >= 4 (random cells are
         * in general position), and as large as the best LP vertex */
        double (*pl)[4] = malloc(sizeof *pl * (size_t)nf);
        int np = cell_planes(&cell, pl);
        int tight = 0;
        for (int f = 0; f < np; f++) {
            double slack = pl[f][3] - (pl[f][0] * m.inscribed.center[0] +
                                       pl[f][1] * m.inscribed.center[1] +
                                       pl[f][2] * m.inscribed.center[2]);
            CHECK(slack >= m.inscribed.radius - 1e-12);
            tight += fabs(slack - m.inscribed.radius) < 1e-9;
        }
        CHECK(tight >= 4);
        CHECK_NEAR(m.inscribed.radius, brute_inscribed_radius(np, pl), 1e-10);
        CHECK(m.fatness >= 1.0 && isfinite(m.fatness));
        /* a Voronoi cell contains its seed; the inscribed centre is inside too */
        free(pl);
        free(off);
        free(fv);
        free(pts);
        free(vid);
        checked++;
    }
    CHECK(checked == n);
    CHECK_NEAR(total, 1.0, 1e-12);

    /* degenerate enclosing-ball inputs */
    vc_ball b;
    double same[12] = {1, 2, 3, 1, 2, 3, 1, 2, 3, 1, 2, 3};
    CHECK(vc_min_enclosing_ball(4, same, NULL, &b) == 0);
    CHECK(b.radius == 0 && b.center[0] == 1 && b.center[1] == 2 && b.center[2] == 3);
    double line[15] = {0, 0, 0, 1, 1, 1, 2, 2, 2, 3, 3, 3, 4, 4, 4};
    CHECK(vc_min_enclosing_ball(5, line, NULL, &b) == 0);
    CHECK_NEAR(b.radius, 2 * sqrt(3.0), 1e-14);
    double ring[3 * 12];
    for (int i = 0; i < 12; i++) { /* co-circular and coplanar */
        ring[3 * i] = cos(i * 3.14159265358979323846 / 6);
        ring[3 * i + 1] = sin(i * 3.14159265358979323846 / 6);
        ring[3 * i + 2] = 5;
    }
    CHECK(vc_min_enclosing_ball(12, ring, NULL, &b) == 0);
    CHECK_NEAR(b.radius, 1.0, 1e-14);
    CHECK_NEAR(b.center[2], 5.0, 1e-14);
    CHECK(vc_min_enclosing_ball(0, ring, NULL, &b) == VC_EPARAM);
    int64_t pick[2] = {0, 6};
    CHECK(vc_min_enclosing_ball(2, ring, pick, &b) == 0);
    CHECK_NEAR(b.radius, 1.0, 1e-14);
    vc_polymesh_free(&mesh);
    vc_seeds_free(&seeds);
}

/* ---- Hausdorff ------------------------------------------------------------ */

/* Icosphere of radius r: the icosahedron subdivided `levels` times. */
static void icosphere(int levels, double r, vc_surface *s)
{
    const double t = (1 + sqrt(5.0)) / 2;
    double v0[12][3] = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                        {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
    int f0[20][3] = {{0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9},
                     {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8}, {3, 9, 4}, {3, 4, 2},
                     {3, 2, 6}, {3, 6, 8}, {3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10},
                     {8, 6, 7}, {9, 8, 1}};
    int64_t nt = 20, nv = 12;
    int64_t cap_t = 20, cap_v = 12;
    for (int l = 0; l < levels; l++) {
        cap_t *= 4;
        cap_v += 3 * (cap_t / 4); /* three new midpoints per old triangle */
    }
    s->xyz = malloc(sizeof(double) * 3 * (size_t)cap_v);
    s->tri = malloc(sizeof(int64_t) * 3 * (size_t)cap_t);
    for (int i = 0; i < 12; i++)
        memcpy(s->xyz + 3 * i, v0[i], sizeof v0[i]);
    for (int i = 0; i < 20; i++)
        for (int k = 0; k < 3; k++)
            s->tri[3 * i + k] = f0[i][k];
    for (int l = 0; l < levels; l++) {
        /* midpoints without sharing: duplicates are harmless here, the
         * surface is still watertight geometrically */
        int64_t *nt_tri = malloc(sizeof(int64_t) * 12 * (size_t)nt);
        for (int64_t f = 0; f < nt; f++) {
            int64_t a = s->tri[3 * f], b = s->tri[3 * f + 1], c = s->tri[3 * f + 2];
            int64_t ab = nv++, bc = nv++, ca = nv++;
            for (int d = 0; d < 3; d++) {
                s->xyz[3 * ab + d] = 0.5 * (s->xyz[3 * a + d] + s->xyz[3 * b + d]);
                s->xyz[3 * bc + d] = 0.5 * (s->xyz[3 * b + d] + s->xyz[3 * c + d]);
                s->xyz[3 * ca + d] = 0.5 * (s->xyz[3 * c + d] + s->xyz[3 * a + d]);
            }
            int64_t q[4][3] = {{a, ab, ca}, {b, bc, ab}, {c, ca, bc}, {ab, bc, ca}};
            memcpy(nt_tri + 12 * f, q, sizeof q);
        }
        free(s->tri);
        s->tri = nt_tri;
        nt *= 4;
    }
    (void)cap_v;
    for (int64_t i = 0; i < nv; i++) {
        double *p = s->xyz + 3 * i;
        double len = sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
        for (int d = 0; d < 3; d++)
            p[d] *= r / len;
    }
    s->n_vertices = nv;
    s->n_triangles = nt;
}

static void test_hausdorff(void)
{
    vc_surface a, b;
    vc_error err;
    icosphere(4, 1.0, &a); /* 5120 triangles */
    icosphere(4, 1.01, &b);
    vc_hausdorff_result h;
    CHECK(vc_hausdorff(&a, &a, 0, &h, &err) == 0);
    CHECK(h.distance <= 1e-15); /* a sample's distance to its own triangle: rounding only */
    CHECK(h.n_samples_a > 5120 * 3);
    double diag = 2 * sqrt(3.0);
    CHECK(vc_hausdorff(&a, &b, 0, &h, &err) == 0);
    CHECK_NEAR(h.diagonal, diag, 1e-3); /* the icosphere's box is slightly inside [-1,1]^3 */
    /* 0.01 plus at most the chord sagitta (edge ~0.06: < 5e-4) */
    CHECK(h.distance >= 0.01 - 1e-9 && h.distance <= 0.0106);
    CHECK_NEAR(h.normalised, 0.01 / diag, 0.0006 / diag);
    CHECK(h.error_bound > 0 && h.error_bound <= h.spacing);

    /* a translated copy: exactly the translation (parallel faces) */
    vc_surface_free(&b);
    icosphere(2, 1.0, &b);
    for (int64_t i = 0; i < b.n_vertices; i++)
        b.xyz[3 * i] += 0.125;
    vc_hausdorff_result h1, h2;
#ifdef _OPENMP
    omp_set_num_threads(1);
#endif
    CHECK(vc_hausdorff(&a, &b, 0.01, &h1, &err) == 0);
#ifdef _OPENMP
    omp_set_num_threads(2);
#endif
    CHECK(vc_hausdorff(&a, &b, 0.01, &h2, &err) == 0);
    CHECK(h1.distance == h2.distance && h1.a_to_b == h2.a_to_b && h1.b_to_a == h2.b_to_a);
    CHECK(h1.n_samples_a == h2.n_samples_a && h1.n_samples_b == h2.n_samples_b);
    CHECK(h1.distance >= 0.125 - 1e-12);
    CHECK(h1.distance <= 0.125 + 0.03); /* coarser b (edge ~0.3): plus its chord sagitta */

    vc_surface empty = {0, NULL, 0, NULL, NULL, 0, NULL};
    CHECK(vc_hausdorff(&a, &empty, 0, &h, &err) == VC_EINPUT);
    vc_surface_free(&a);
    vc_surface_free(&b);
}

static int cmp_double_test(const void *x, const void *y)
{
    const double a = *(const double *)x, b = *(const double *)y;
    return (a > b) - (a < b);
}

static void test_stats(void)
{
    double v[100];
    for (int i = 0; i < 100; i++)
        v[99 - i] = i + 1; /* 100 .. 1 */
    vc_stats st;
    CHECK(vc_stats_compute(v, 100, &st) == 0);
    CHECK(st.n == 100 && st.min == 1 && st.max == 100);
    CHECK_NEAR(st.mean, 50.5, 1e-14);
    CHECK_NEAR(st.p50, 50.5, 1e-14); /* numpy.percentile(range(1, 101), 50) */
    CHECK_NEAR(st.p1, 1.99, 1e-12);
    CHECK_NEAR(st.p5, 5.95, 1e-12);
    CHECK_NEAR(st.p95, 95.05, 1e-12);
    CHECK_NEAR(st.p99, 99.01, 1e-12);
    double w[5] = {NAN, 3, INFINITY, 1, 2};
    CHECK(vc_stats_compute(w, 5, &st) == 0);
    CHECK(st.n == 4 && st.min == 1 && isinf(st.max) && isinf(st.mean));
    CHECK_NEAR(st.p50, 2.5, 1e-15);
    CHECK(vc_stats_compute(w, 0, &st) == 0);
    CHECK(st.n == 0 && isnan(st.min) && isnan(st.p99));
    double one = 7;
    CHECK(vc_stats_compute(&one, 1, &st) == 0);
    CHECK(st.min == 7 && st.p1 == 7 && st.p99 == 7 && st.mean == 7);
    /* signs, zeros, infinities, subnormals: the radix sort's key mapping */
    double s[8] = {-0.0, 3.5, -INFINITY, 1e-310, -2.25, 0.0, -1e-310, 42};
    CHECK(vc_stats_compute(s, 8, &st) == 0);
    CHECK(st.n == 8 && isinf(st.min) && st.min < 0 && st.max == 42);
    CHECK_NEAR(st.p50, 0.0, 1e-300); /* between the two zeros */
    /* a large array against qsort's order: every percentile a value of it */
    enum { M = 100001 };
    double *big = malloc(sizeof(double) * M), *sorted = malloc(sizeof(double) * M);
    unsigned u = 12345;
    for (int i = 0; i < M; i++) {
        u = u * 1103515245u + 12345u;
        big[i] = ((double)(u >> 8) / 16777216.0 - 0.5) * ldexp(1.0, (int)(u % 40) - 20);
        sorted[i] = big[i];
    }
    qsort(sorted, M, sizeof(double), cmp_double_test);
    CHECK(vc_stats_compute(big, M, &st) == 0);
    CHECK(st.min == sorted[0] && st.max == sorted[M - 1]);
    CHECK(st.p1 == sorted[1000] && st.p50 == sorted[50000] && st.p99 == sorted[99000]);
    free(big);
    free(sorted);
}

int main(void)
{
    test_triangles();
    test_cube_and_lp_degenerate();
    test_lp_fallback();
    test_tetrahedra();
    test_random_cells();
    test_hausdorff();
    test_stats();
    if (failures) {
        fprintf(stderr, "test_quality: %d failures\n", failures);
        return 1;
    }
    printf("test_quality: all checks passed\n");
    return 0;
}
