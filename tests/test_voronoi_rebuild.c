/* vc_voronoi_rebuild: after a few seeds move, the mesh made from the kept
 * cells (only those next to a moved seed built again) is the mesh a fresh
 * vc_voronoi_build gives, byte for byte, for random seeds, exact lattices
 * with a shell of seeds that are not kept (VoroCrust's layout), both
 * neighbour sources, 1 and 2 threads, moves chained over several rebuilds,
 * a moved seed that is not kept, one that leaves the seeds' bounds; and
 * the refusals. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "vorocrust/random.h"
#include "vorocrust/voronoi.h"

#include "test_check.h"
#include "test_polymesh_compare.h"

/* same_mesh, and the faces' neighbours and other seeds, the cells'
 * seeds and volumes */
static int identical(const vc_polymesh *a, const vc_polymesh *b)
{
    if (!same_mesh(a, b))
        return 0;
    const size_t nf = (size_t)a->n_faces, nc = (size_t)a->n_cells;
    return !memcmp(a->face_neighbour, b->face_neighbour, nf * sizeof(int64_t)) &&
           !memcmp(a->face_other_seed, b->face_other_seed, nf * sizeof(int64_t)) &&
           !memcmp(a->face_area, b->face_area, nf * sizeof(double)) &&
           !memcmp(a->cell_seed, b->cell_seed, nc * sizeof(int64_t)) &&
           !memcmp(a->cell_volume, b->cell_volume, nc * sizeof(double));
}

static void explain(const vc_polymesh *a, const vc_polymesh *b)
{
    fprintf(stderr, "  points %lld %lld faces %lld %lld cells %lld %lld\n", (long long)a->n_points,
            (long long)b->n_points, (long long)a->n_faces, (long long)b->n_faces,
            (long long)a->n_cells, (long long)b->n_cells);
    if (a->n_points == b->n_points)
        for (int64_t i = 0; i < a->n_points; i++)
            if (memcmp(a->points + 3 * i, b->points + 3 * i, 24)) {
                fprintf(stderr, "  point %lld: %.17g %.17g %.17g vs %.17g %.17g %.17g\n",
                        (long long)i, a->points[3 * i], a->points[3 * i + 1], a->points[3 * i + 2],
                        b->points[3 * i], b->points[3 * i + 1], b->points[3 * i + 2]);
                break;
            }
    if (a->n_faces == b->n_faces) {
        int64_t fo = -1, fv = -1, fw = -1, fn = -1, fs = -1;
        for (int64_t f = 0; f < a->n_faces; f++) {
            if (fo < 0 && a->face_offsets[f + 1] != b->face_offsets[f + 1])
                fo = f;
            if (fw < 0 && a->face_owner[f] != b->face_owner[f])
                fw = f;
            if (fn < 0 && a->face_neighbour[f] != b->face_neighbour[f])
                fn = f;
            if (fs < 0 && a->face_other_seed[f] != b->face_other_seed[f])
                fs = f;
        }
        for (int64_t i = 0; fo < 0 && i < a->face_offsets[a->n_faces]; i++)
            if (a->face_vertices[i] != b->face_vertices[i]) {
                fv = i;
                break;
            }
        fprintf(stderr, "  first differing face offset %lld vertex %lld owner %lld neighbour %lld "
                "other seed %lld\n", (long long)fo, (long long)fv, (long long)fw, (long long)fn,
                (long long)fs);
    }
    if (a->n_cells == b->n_cells)
        for (int64_t c = 0; c < a->n_cells; c++)
            if (a->cell_volume[c] != b->cell_volume[c]) {
                fprintf(stderr, "  cell %lld: %.17g vs %.17g\n", (long long)c, a->cell_volume[c],
                        b->cell_volume[c]);
                break;
            }
}

static void options(vc_voronoi_options *o, int threads, int neighbours, const double *box)
{
    vc_voronoi_options_default(o);
    o->threads = threads;
    o->neighbours = neighbours;
    if (box) {
        o->has_box = 1;
        memcpy(o->box, box, sizeof o->box);
    }
}

/* Moves `count` seeds among [first, last) (distinct, at random, none on
 * the bounding box of the set: its bounds stay) by up to `step` per axis,
 * kept inside [lo, hi] and strictly inside the bounds; their indices into
 * moved. */
static void move_some(vc_seeds *s, vc_rng *rng, int64_t first, int64_t last, int count,
                      double step, double lo, double hi, int64_t *moved)
{
    double blo[3] = {INFINITY, INFINITY, INFINITY}, bhi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int64_t i = 0; i < s->n; i++)
        for (int d = 0; d < 3; d++) {
            blo[d] = fmin(blo[d], s->xyz[3 * i + d]);
            bhi[d] = fmax(bhi[d], s->xyz[3 * i + d]);
        }
    for (int q = 0; q < count; q++) {
        int64_t i;
        int again;
        do {
            i = first + (int64_t)(vc_rng_uniform(rng) * (double)(last - first));
            if (i >= last)
                i = last - 1;
            again = 0;
            for (int p = 0; p < q; p++)
                again |= moved[p] == i;
            for (int d = 0; d < 3; d++)
                again |= s->xyz[3 * i + d] == blo[d] || s->xyz[3 * i + d] == bhi[d];
        } while (again);
        moved[q] = i;
        for (int d = 0; d < 3; d++) {
            const double a = fmax(lo, blo[d] + 1e-6), b = fmin(hi, bhi[d] - 1e-6);
            double x = s->xyz[3 * i + d] + step * (2 * vc_rng_uniform(rng) - 1);
            s->xyz[3 * i + d] = x < a ? a : x > b ? b : x;
        }
    }
}

/* Builds with the cells kept, then `rounds` times moves `count` seeds of
 * [first, last) and checks the rebuild against a fresh build (and, the
 * first time, that fewer cells were built again than there are). */
static void check_rounds(const char *name, vc_seeds *s, const double *box, int neighbours,
                         int threads, int64_t first, int64_t last, int count, double step,
                         double lo, double hi, int rounds)
{
    vc_voronoi_options o;
    options(&o, threads, neighbours, box);
    vc_error err = {0, ""};
    vc_polymesh m;
    vc_voronoi_cells *cells = NULL;
    if (vc_voronoi_build_keep(s, &o, &m, &cells, &err) != 0) {
        CHECKF(0, "%s: build: %s", name, err.msg);
        return;
    }
    CHECKF(vc_voronoi_cells_rebuilt(cells) == m.n_cells, "%s: the build made %lld cells of %lld",
           name, (long long)vc_voronoi_cells_rebuilt(cells), (long long)m.n_cells);
    vc_polymesh_free(&m);
    vc_rng rng;
    vc_rng_init(&rng, 7, (uint64_t)threads * 31 + (uint64_t)neighbours);
    int64_t moved[64];
    for (int r = 0; r < rounds; r++) {
        move_some(s, &rng, first, last, count, step, lo, hi, moved);
        vc_polymesh a, b;
        if (vc_voronoi_rebuild(cells, s, moved, count, &o, &a, &err) != 0) {
            CHECKF(0, "%s: rebuild %d: %s", name, r, err.msg);
            break;
        }
        const int64_t again = vc_voronoi_cells_rebuilt(cells);
        if (vc_voronoi_build(s, &o, &b, &err) != 0) {
            CHECKF(0, "%s: fresh build %d: %s", name, r, err.msg);
            vc_polymesh_free(&a);
            break;
        }
        if (!identical(&a, &b))
            explain(&a, &b);
        CHECKF(identical(&a, &b), "%s: rebuild %d (%d seeds moved, %lld cells built again) "
               "differs from a fresh build", name, r, count, (long long)again);
        CHECKF(again > 0 && again < a.n_cells / 2, "%s: rebuild %d built %lld of %lld cells "
               "again for %d moved seeds", name, r, (long long)again, (long long)a.n_cells, count);
        char report[256];
        CHECKF(vc_polymesh_validate(&a, 0, report, sizeof report) == 0, "%s: rebuild %d: %s",
               name, r, report);
        vc_polymesh_free(&a);
        vc_polymesh_free(&b);
    }
    vc_voronoi_cells_free(cells);
}

/* n uniform random seeds in the unit cube, stream seed of the generator;
 * labels 1, or 1 and 2 alternately. */
static void unit_cube_seeds(vc_seeds *s, int64_t n, uint64_t seed, int two_labels)
{
    vc_seeds_alloc(s, n, NULL);
    vc_rng rng;
    vc_rng_init(&rng, seed, 0);
    for (int64_t i = 0; i < 3 * n; i++)
        s->xyz[i] = vc_rng_uniform(&rng);
    for (int64_t i = 0; i < n; i++)
        s->label[i] = two_labels ? 1 + (int32_t)(i % 2) : 1;
}

static void test_random(int threads, int neighbours)
{
    const int64_t n = 1500;
    vc_seeds s;
    unit_cube_seeds(&s, n, 11, 0);
    const double box[6] = {0, 0, 0, 1, 1, 1};
    char name[64];
    snprintf(name, sizeof name, "random, %d threads, neighbours %d", threads, neighbours);
    check_rounds(name, &s, box, neighbours, threads, 0, n, 12, 0.02, 0, 1, 3);
    vc_seeds_free(&s);
}

/* A cubic lattice of kept seeds (every corner a tie of eight cells) inside
 * a shell of seeds that are not kept, no box: the layout of VoroCrust's
 * octree seeds inside its outside seeds. Lattice seeds move by a quarter
 * of the spacing, so that ties are broken and made near. */
static void test_lattice_in_shell(int threads, int neighbours)
{
    const int k = 10;
    const int64_t n_lat = (int64_t)k * k * k, n_shell = 600, n = n_lat + n_shell;
    vc_seeds s;
    vc_seeds_alloc(&s, n, NULL);
    for (int64_t i = 0; i < n_lat; i++) {
        s.xyz[3 * i + 0] = ((double)(i % k) + 0.5) / k;
        s.xyz[3 * i + 1] = ((double)((i / k) % k) + 0.5) / k;
        s.xyz[3 * i + 2] = ((double)(i / ((int64_t)k * k)) + 0.5) / k;
        s.label[i] = 1;
    }
    vc_rng rng;
    vc_rng_init(&rng, 5, 1);
    for (int64_t i = n_lat; i < n; i++) {
        double u[3], q = 0;
        do {
            for (int d = 0; d < 3; d++)
                u[d] = 2 * vc_rng_uniform(&rng) - 1;
            q = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
        } while (!(q > 0.1 && q <= 1));
        for (int d = 0; d < 3; d++)
            s.xyz[3 * i + d] = 0.5 + 1.2 * u[d] / q;
        s.label[i] = 0;
    }
    char name[64];
    snprintf(name, sizeof name, "lattice in a shell, %d threads, neighbours %d", threads,
             neighbours);
    check_rounds(name, &s, NULL, neighbours, threads, 0, n_lat, 10, 0.25 / k, 0.02, 0.98, 3);
    /* a seed that is not kept moves: the cells it bounds change */
    snprintf(name, sizeof name, "shell seeds moved, %d threads", threads);
    check_rounds(name, &s, NULL, neighbours, threads, n_lat, n, 5, 0.05, -0.7, 1.7, 2);
    vc_seeds_free(&s);
}

/* A moved seed beyond the first seeds' bounds: every cell again, and
 * still the fresh build's mesh; then a rebuild from there. */
static void test_outside_bounds(void)
{
    const int64_t n = 800;
    vc_seeds s;
    unit_cube_seeds(&s, n, 3, 1);
    vc_voronoi_options o;
    options(&o, 2, 0, NULL);
    vc_error err = {0, ""};
    vc_polymesh m, fresh;
    vc_voronoi_cells *cells = NULL;
    if (vc_voronoi_build_keep(&s, &o, &m, &cells, &err) != 0) {
        CHECKF(0, "outside: build: %s", err.msg);
        return;
    }
    vc_polymesh_free(&m);
    int64_t moved[1] = {17};
    s.xyz[3 * 17] = 1.5; /* beyond every seed's x */
    CHECKF(vc_voronoi_rebuild(cells, &s, moved, 1, &o, &m, &err) == 0, "outside: rebuild: %s",
           err.msg);
    CHECKF(vc_voronoi_cells_rebuilt(cells) == m.n_cells, "outside: %lld cells built again of %lld",
           (long long)vc_voronoi_cells_rebuilt(cells), (long long)m.n_cells);
    CHECK(vc_voronoi_build(&s, &o, &fresh, &err) == 0);
    CHECKF(identical(&m, &fresh), "outside: the rebuild differs from a fresh build");
    vc_polymesh_free(&m);
    vc_polymesh_free(&fresh);
    /* and on from the new cells */
    moved[0] = 101;
    s.xyz[3 * 101 + 1] += 0.01;
    CHECKF(vc_voronoi_rebuild(cells, &s, moved, 1, &o, &m, &err) == 0, "outside: second rebuild: "
           "%s", err.msg);
    CHECK(vc_voronoi_build(&s, &o, &fresh, &err) == 0);
    CHECKF(identical(&m, &fresh), "outside: the second rebuild differs from a fresh build");
    CHECKF(vc_voronoi_cells_rebuilt(cells) < 60, "outside: %lld cells built again for one seed",
           (long long)vc_voronoi_cells_rebuilt(cells));
    vc_polymesh_free(&m);
    vc_polymesh_free(&fresh);

    /* nothing moved: no cell built again, the same mesh; a seed listed twice
     * counts once */
    CHECK(vc_voronoi_rebuild(cells, &s, moved, 0, &o, &m, &err) == 0);
    CHECK(vc_voronoi_cells_rebuilt(cells) == 0);
    CHECK(vc_voronoi_build(&s, &o, &fresh, &err) == 0);
    CHECKF(identical(&m, &fresh), "outside: a rebuild without moves differs from a fresh build");
    vc_polymesh_free(&m);
    vc_polymesh_free(&fresh);
    {
        const int64_t twice[2] = {200, 200};
        s.xyz[3 * 200 + 2] += 0.01;
        CHECK(vc_voronoi_rebuild(cells, &s, twice, 2, &o, &m, &err) == 0);
        CHECK(vc_voronoi_build(&s, &o, &fresh, &err) == 0);
        CHECKF(identical(&m, &fresh), "outside: a seed listed twice: differs from a fresh build");
        vc_polymesh_free(&m);
        vc_polymesh_free(&fresh);
    }

    /* refusals: another seed count, another kept set, an index out of range */
    vc_seeds fewer = {n - 1, s.xyz, s.label};
    CHECK(vc_voronoi_rebuild(cells, &fewer, moved, 1, &o, &m, &err) == VC_EPARAM);
    s.label[5] = 0;
    CHECK(vc_voronoi_rebuild(cells, &s, moved, 1, &o, &m, &err) == VC_EPARAM);
    s.label[5] = 1;
    moved[0] = n;
    CHECK(vc_voronoi_rebuild(cells, &s, moved, 1, &o, &m, &err) == VC_EPARAM);
    /* coincident after a move: the build's error, naming both seeds */
    moved[0] = 3;
    memcpy(s.xyz + 3 * 3, s.xyz + 3 * 4, 3 * sizeof(double));
    CHECK(vc_voronoi_rebuild(cells, &s, moved, 1, &o, &m, &err) == VC_EINPUT);
    CHECKF(strstr(err.msg, "coincide") != NULL, "coincident: %s", err.msg);
    /* the kept cells are then of no use: refused until built again */
    s.xyz[3 * 3] += 0.001;
    CHECK(vc_voronoi_rebuild(cells, &s, moved, 1, &o, &m, &err) == VC_EPARAM);
    vc_voronoi_cells_free(cells);
    vc_seeds_free(&s);
}

int main(void)
{
    for (int threads = 1; threads <= 2; threads++) {
        test_random(threads, VC_NEIGHBOURS_GRID);
        test_random(threads, VC_NEIGHBOURS_TREE);
        test_lattice_in_shell(threads, VC_NEIGHBOURS_AUTO);
        test_lattice_in_shell(threads, VC_NEIGHBOURS_TREE);
    }
    test_outside_bounds();
    if (failures)
        fprintf(stderr, "test_voronoi_rebuild: %d failure(s)\n", failures);
    return failures ? 1 : 0;
}
