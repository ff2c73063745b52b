/* The faces of a mesh read from a .vtu file, where each cell lists its own
 * copy of every face: which copies are the same face (the same vertex
 * set), and the boundary (faces listed by one cell only) as a triangle
 * surface. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "quality_internal.h"

typedef struct face_key {
    uint64_t hash;
    int64_t face;
} face_key;

/* The face's ids sorted into buf (faces are small: insertion sort). */
static int64_t sorted_ids(const vc_vtu_mesh *m, int64_t f, int64_t *buf)
{
    int64_t n = m->face_offsets[f + 1] - m->face_offsets[f];
    for (int64_t i = 0; i < n; i++) {
        int64_t x = m->face_vertices[m->face_offsets[f] + i], j = i;
        while (j > 0 && buf[j - 1] > x) {
            buf[j] = buf[j - 1];
            j--;
        }
        buf[j] = x;
    }
    return n;
}

/* Stable LSD radix sort of the keys by hash, 16 bits per pass: equal
 * hashes keep face order, so the result is deterministic. */
static int radix_sort_keys(face_key *key, int64_t n)
{
    face_key *tmp = malloc(sizeof *tmp * (size_t)(n ? n : 1));
    int64_t *count = malloc(sizeof *count * 65536);
    if (!tmp || !count) {
        free(tmp);
        free(count);
        return -1;
    }
    for (int shift = 0; shift < 64; shift += 16) {
        memset(count, 0, sizeof *count * 65536);
        for (int64_t i = 0; i < n; i++)
            count[(key[i].hash >> shift) & 0xffff]++;
        int64_t sum = 0;
        for (int d = 0; d < 65536; d++) {
            int64_t c = count[d];
            count[d] = sum;
            sum += c;
        }
        for (int64_t i = 0; i < n; i++)
            tmp[count[(key[i].hash >> shift) & 0xffff]++] = key[i];
        face_key *t = key;
        memcpy(t, tmp, sizeof *tmp * (size_t)n);
    }
    free(tmp);
    free(count);
    return 0;
}

/* Sets uses[f] to the number of faces (itself included) with the same
 * vertex set; returns the number of distinct faces, or -1 (out of memory).
 * Faces are bucketed by a hash of their sorted ids, then compared exactly
 * within each bucket (buckets in parallel: each owns its faces). */
int64_t vc_mesh_face_uses(const vc_vtu_mesh *m, int64_t *uses, int64_t *twin)
{
    int64_t nf = m->n_faces, maxlen = 0;
    for (int64_t f = 0; f < nf; f++)
        if (m->face_offsets[f + 1] - m->face_offsets[f] > maxlen)
            maxlen = m->face_offsets[f + 1] - m->face_offsets[f];
    face_key *key = malloc(sizeof *key * (size_t)(nf ? nf : 1));
    int64_t *run = malloc(sizeof *run * (size_t)(nf + 1));
    if (!key || !run) {
        free(key);
        free(run);
        return -1;
    }
    int oom = 0;
#pragma omp parallel reduction(| : oom)
    {
        int64_t *a = malloc(sizeof *a * (size_t)(maxlen + 1));
        oom |= !a;
#pragma omp for schedule(static)
        for (int64_t f = 0; f < nf; f++) {
            if (!a)
                continue;
            int64_t n = sorted_ids(m, f, a);
            uint64_t h = 1469598103934665603ULL ^ (uint64_t)n;
            for (int64_t i = 0; i < n; i++) {
                h ^= (uint64_t)a[i] + 0x9e3779b97f4a7c15ULL + (h << 6) + (h >> 2);
                h *= 1099511628211ULL;
            }
            key[f].hash = h;
            key[f].face = f;
        }
        free(a);
    }
    if (oom || radix_sort_keys(key, nf) != 0) {
        free(key);
        free(run);
        return -1;
    }
    int64_t nrun = 0;
    for (int64_t i = 0; i < nf; i++)
        if (i == 0 || key[i].hash != key[i - 1].hash)
            run[nrun++] = i;
    run[nrun] = nf;
    int64_t distinct = 0;
#pragma omp parallel reduction(+ : distinct) reduction(| : oom)
    {
        int64_t *a = malloc(sizeof *a * (size_t)(2 * maxlen + 2));
        oom |= !a;
#pragma omp for schedule(dynamic, 4096)
        for (int64_t r = 0; r < nrun; r++) {
            if (!a)
                continue;
            int64_t *b = a + maxlen + 1;
            int64_t i = run[r], j = run[r + 1];
            /* group exactly equal vertex sets (runs are almost always 1 or
             * 2 long) */
            for (int64_t k = i; k < j; k++)
                uses[key[k].face] = 0;
            for (int64_t k = i; k < j; k++) {
                if (uses[key[k].face])
                    continue;
                int64_t nk = sorted_ids(m, key[k].face, a), count = 1;
                for (int64_t l = k + 1; l < j; l++) {
                    if (uses[key[l].face])
                        continue;
                    int64_t nl = sorted_ids(m, key[l].face, b);
                    if (nl == nk && !memcmp(a, b, sizeof *a * (size_t)nk))
                        count++, uses[key[l].face] = -1;
                }
                uses[key[k].face] = count;
                if (twin)
                    twin[key[k].face] = -1;
                for (int64_t l = k + 1; l < j; l++)
                    if (uses[key[l].face] == -1) {
                        uses[key[l].face] = count;
                        /* a face of two cells: each copy names the other */
                        if (twin) {
                            twin[key[l].face] = count == 2 ? key[k].face : -1;
                            if (count == 2)
                                twin[key[k].face] = key[l].face;
                        }
                    }
                distinct++;
            }
        }
        free(a);
    }
    free(key);
    free(run);
    return oom ? -1 : distinct;
}

/* The boundary faces as a triangle surface on the mesh points (polygons
 * fanned from their vertex average, which is appended as a point). */
int vc_mesh_boundary_surface(const vc_vtu_mesh *m, const int64_t *uses, vc_surface *s)
{
    int64_t nt = 0, nextra = 0;
    for (int64_t f = 0; f < m->n_faces; f++) {
        if (uses[f] != 1)
            continue;
        int64_t n = m->face_offsets[f + 1] - m->face_offsets[f];
        nt += n == 3 ? 1 : n;
        nextra += n == 3 ? 0 : 1;
    }
    s->n_vertices = m->n_points + nextra;
    s->n_triangles = nt;
    s->xyz = malloc(sizeof(double) * 3 * (size_t)(s->n_vertices ? s->n_vertices : 1));
    s->tri = malloc(sizeof(int64_t) * 3 * (size_t)(nt ? nt : 1));
    if (!s->xyz || !s->tri)
        return -1;
    memcpy(s->xyz, m->points, sizeof(double) * 3 * (size_t)m->n_points);
    int64_t t = 0, v = m->n_points;
    for (int64_t f = 0; f < m->n_faces; f++) {
        if (uses[f] != 1)
            continue;
        const int64_t *id = m->face_vertices + m->face_offsets[f];
        int64_t n = m->face_offsets[f + 1] - m->face_offsets[f];
        if (n == 3) {
            memcpy(s->tri + 3 * t++, id, 3 * sizeof *id);
            continue;
        }
        double *c = s->xyz + 3 * v;
        c[0] = c[1] = c[2] = 0;
        for (int64_t i = 0; i < n; i++)
            for (int d = 0; d < 3; d++)
                c[d] += m->points[3 * id[i] + d] / (double)n;
        for (int64_t i = 0; i < n; i++) {
            s->tri[3 * t] = v;
            s->tri[3 * t + 1] = id[i];
            s->tri[3 * t + 2] = id[(i + 1) % n];
            t++;
        }
        v++;
    }
    return 0;
}

