/* The library is re-entrant: a program may read surfaces on several
 * threads at once (a mesher service, a batch over files), and each read
 * gives what it gives alone. vc_surface_read merges the repeated vertices
 * of a triangle soup by sorting; its comparator once read a file-scope
 * pointer, so two reads at once could sort one file by the other's
 * coordinates. Two soups of different sizes are read on four threads, 48
 * times each, and compared bit for bit with a read on one thread. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "vorocrust/surface.h"

#include "test_check.h"
#include "test_surface_util.h"

/* A UV sphere written as a soup: every triangle with its own three
 * vertex lines, so the reader merges three copies of nearly every vertex. */
static void write_soup(const char *path, int nu, int nv, double radius, double shift)
{
    builder b = {0};
    make_sphere(&b, nu, nv);
    FILE *f = fopen(path, "w");
    CHECK(f != NULL);
    if (!f) {
        vc_surface_free(&b.s);
        return;
    }
    for (int64_t t = 0; t < b.s.n_triangles; t++) {
        for (int k = 0; k < 3; k++) {
            const double *x = b.s.xyz + 3 * b.s.tri[3 * t + k];
            fprintf(f, "v %.17g %.17g %.17g\n", radius * x[0] + shift, radius * x[1], radius * x[2]);
        }
        fprintf(f, "f %lld %lld %lld\n", (long long)(3 * t + 1), (long long)(3 * t + 2),
                (long long)(3 * t + 3));
    }
    fclose(f);
    vc_surface_free(&b.s);
}

static int same_surface(const vc_surface *a, const vc_surface *b)
{
    return a->n_vertices == b->n_vertices && a->n_triangles == b->n_triangles &&
           memcmp(a->xyz, b->xyz, sizeof(double) * 3 * (size_t)a->n_vertices) == 0 &&
           memcmp(a->tri, b->tri, sizeof(int64_t) * 3 * (size_t)a->n_triangles) == 0;
}

int main(void)
{
    const char *dir = getenv("VC_TMP") ? getenv("VC_TMP") : "/tmp";
    char path[2][1024];
    snprintf(path[0], sizeof path[0], "%s/test_reentrant_a.obj", dir);
    snprintf(path[1], sizeof path[1], "%s/test_reentrant_b.obj", dir);
    write_soup(path[0], 96, 48, 1.0, 0.0);
    write_soup(path[1], 60, 70, 3.0, 5.0);

    vc_surface ref[2];
    for (int i = 0; i < 2; i++) {
        vc_surface_report rep;
        vc_error err;
        CHECK_MSG(vc_surface_read(path[i], &ref[i], &rep, &err) == 0, err.msg);
        /* the soup's copies were merged: a closed sphere's vertex count */
        CHECK(rep.n_duplicate_vertices > 0);
    }
    CHECK(ref[0].n_vertices == 96 * 47 + 2 && ref[1].n_vertices == 60 * 69 + 2);

    int mismatches = 0, failed = 0;
#pragma omp parallel for schedule(dynamic, 1) num_threads(4) reduction(+ : mismatches, failed)
    for (int k = 0; k < 96; k++) {
        vc_surface s;
        vc_surface_report rep;
        vc_error err;
        if (vc_surface_read(path[k % 2], &s, &rep, &err) != 0) {
            failed++;
            continue;
        }
        mismatches += !same_surface(&s, &ref[k % 2]);
        vc_surface_free(&s);
    }
    CHECKF(failed == 0 && mismatches == 0, "%d reads failed, %d differ from the one-thread read",
           failed, mismatches);
    printf("96 reads on 4 threads: %d failed, %d differ\n", failed, mismatches);
    vc_surface_free(&ref[0]);
    vc_surface_free(&ref[1]);
    remove(path[0]);
    remove(path[1]);
    return failures ? 1 : 0;
}
