/* vc_polymesh_validate against broken meshes: the Voronoi mesh of 64
 * jittered lattice seeds passes; a copy with one defect put in (a face
 * repeating a vertex, a vertex index out of range, a face of zero area, a
 * face's cycle reversed, a vertex moved out of its cells, a cell listing
 * another cell's face, a cell of negative volume) fails with that defect
 * named in the report's first line; the report is the same on 1 and 2
 * threads (the faces and cells are checked in parallel, then reported in
 * order). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <omp.h>

#include "vorocrust/polymesh.h"
#include "vorocrust/random.h"
#include "vorocrust/voronoi.h"

#include "test_check.h"

static int build(vc_polymesh *m)
{
    vc_seeds s;
    if (vc_seeds_alloc(&s, 64, NULL) != 0)
        return -1;
    vc_rng rng;
    vc_rng_init(&rng, 7, 0);
    for (int i = 0; i < 64; i++) {
        const int c[3] = {i % 4, (i / 4) % 4, i / 16};
        for (int d = 0; d < 3; d++)
            s.xyz[3 * i + d] = c[d] + 0.5 + 0.3 * (vc_rng_uniform(&rng) - 0.5);
    }
    vc_voronoi_options opt;
    vc_voronoi_options_default(&opt);
    opt.has_box = 1;
    const double box[6] = {0, 0, 0, 4, 4, 4};
    memcpy(opt.box, box, sizeof box);
    vc_error err = {0, ""};
    const int rc = vc_voronoi_build(&s, &opt, m, &err);
    CHECKF(rc == 0, "build: %s", err.msg);
    vc_seeds_free(&s);
    return rc;
}

/* Validates on 1 and 2 threads; expects the same report, and want (NULL:
 * no problem) in its first line. */
static void expect(const vc_polymesh *m, const char *name, const char *want)
{
    char r1[4096], r2[4096];
    omp_set_num_threads(1);
    const int64_t n1 = vc_polymesh_validate(m, 0, r1, sizeof r1);
    omp_set_num_threads(2);
    const int64_t n2 = vc_polymesh_validate(m, 0, r2, sizeof r2);
    CHECKF(n1 == n2 && !strcmp(r1, r2), "%s: %lld problems on 1 thread, %lld on 2; reports\n%s---\n%s",
           name, (long long)n1, (long long)n2, r1, r2);
    if (!want) {
        CHECKF(n1 == 0, "%s: %lld problems:\n%s", name, (long long)n1, r1);
        return;
    }
    const char *nl = strchr(r1, '\n');
    const size_t first = nl ? (size_t)(nl - r1) : strlen(r1);
    char line[1024];
    snprintf(line, sizeof line, "%.*s", (int)(first < sizeof line - 1 ? first : sizeof line - 1), r1);
    CHECKF(n1 > 0 && strstr(line, want), "%s: %lld problems, first \"%s\", expected \"%s\"", name,
           (long long)n1, line, want);
}

int main(void)
{
    vc_polymesh m;
    if (build(&m) != 0)
        return 1;
    expect(&m, "valid", NULL);
    CHECK(m.n_interior_faces > 10 && m.n_cells == 64);

    /* face 0 repeats its first vertex */
    int64_t *fv = m.face_vertices + m.face_offsets[0];
    int64_t saved = fv[1];
    fv[1] = fv[0];
    expect(&m, "repeated vertex", "repeats vertex");
    fv[1] = saved;

    /* an index out of range */
    saved = fv[0];
    fv[0] = m.n_points;
    expect(&m, "index out of range", "out of range");
    fv[0] = saved;

    /* no area */
    double area = m.face_area[3];
    m.face_area[3] = 0;
    expect(&m, "zero area", "has area 0");
    m.face_area[3] = area;

    /* an interior face's cycle reversed: its cells' edges no longer pair */
    const int64_t f = m.n_interior_faces / 2, n = m.face_offsets[f + 1] - m.face_offsets[f];
    fv = m.face_vertices + m.face_offsets[f];
    for (int64_t i = 0; i < n / 2; i++) {
        const int64_t t = fv[i];
        fv[i] = fv[n - 1 - i];
        fv[n - 1 - i] = t;
    }
    expect(&m, "reversed face", "cell ");
    for (int64_t i = 0; i < n / 2; i++) {
        const int64_t t = fv[i];
        fv[i] = fv[n - 1 - i];
        fv[n - 1 - i] = t;
    }
    expect(&m, "restored", NULL);

    /* a vertex of an interior face moved far along the face's normal: the
     * cells on one side are no longer convex */
    double *p = m.points + 3 * fv[0], old[3];
    memcpy(old, p, sizeof old);
    for (int d = 0; d < 3; d++)
        p[d] += 0.5 * m.face_normal[3 * f + d];
    expect(&m, "vertex moved out", "not convex");
    memcpy(p, old, sizeof old);

    /* cell 0 lists a face of the last cell instead of its own first one */
    const int64_t last = m.n_cells - 1;
    saved = m.cell_faces[m.cell_offsets[0]];
    m.cell_faces[m.cell_offsets[0]] = m.cell_faces[m.cell_offsets[last]];
    expect(&m, "foreign face", "listed by");
    m.cell_faces[m.cell_offsets[0]] = saved;

    /* a negative volume */
    const double vol = m.cell_volume[5];
    m.cell_volume[5] = -vol;
    expect(&m, "negative volume", "cell 5 has volume");
    m.cell_volume[5] = vol;
    expect(&m, "all restored", NULL);

    vc_polymesh_free(&m);
    if (failures) {
        fprintf(stderr, "test_polymesh_validate: %d failures\n", failures);
        return 1;
    }
    printf("test_polymesh_validate: all passed\n");
    return 0;
}
