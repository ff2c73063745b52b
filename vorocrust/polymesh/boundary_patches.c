/* The boundary patches of a mesh (see vc_polymesh_boundary_patches): the
 * one place that decides which patch a boundary face belongs to, for
 * every writer. */
#include "vorocrust/polymesh.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* a face's kind: against a non-kept seed, or on one wall of the box */
enum { KEY_SURFACE = 0, KEY_WALL0 = 1, N_KEYS = 7 };
static const char *const key_name[N_KEYS] = {"surface", "xmin", "xmax", "ymin", "ymax", "zmin",
                                             "zmax"};

static int face_key(const vc_polymesh *m, int64_t f)
{
    const int64_t o = m->face_other_seed ? m->face_other_seed[f] : 0;
    if (o >= 0)
        return KEY_SURFACE;
    const int64_t k = VC_WALL_XMIN - o;
    return k >= 0 && k < 6 ? KEY_WALL0 + (int)k : -1;
}

static int cmp_i32(const void *a, const void *b)
{
    const int32_t x = *(const int32_t *)a, y = *(const int32_t *)b;
    return (x > y) - (x < y);
}

void vc_polymesh_face_seed_point(const vc_polymesh *m, int64_t f, double x[3])
{
    const int64_t o = m->face_other_seed ? m->face_other_seed[f] : -1;
    const double *a = m->seed_xyz + 3 * m->cell_seed[m->face_owner[f]];
    if (o >= 0 && o < m->n_seeds) {
        const double *b = m->seed_xyz + 3 * o;
        for (int k = 0; k < 3; k++)
            x[k] = 0.5 * (a[k] + b[k]);
    } else {
        memcpy(x, m->face_centroid + 3 * f, sizeof(double) * 3);
    }
}

int vc_boundary_patches_label_rank(const vc_boundary_patches *p, int32_t label)
{
    if (p->n_labels <= 1)
        return 0;
    const int32_t *hit =
        bsearch(&label, p->label_value, (size_t)p->n_labels, sizeof(int32_t), cmp_i32);
    return hit ? (int)(hit - p->label_value) : 0;
}

void vc_boundary_patches_free(vc_boundary_patches *p)
{
    free(p->name);
    free(p->size);
    free(p->group);
    free(p->face_patch);
    free(p->label_value);
    memset(p, 0, sizeof *p);
}

int vc_polymesh_boundary_patches(const vc_polymesh *m, vc_boundary_patches *out, int64_t *bad_face)
{
    memset(out, 0, sizeof *out);
    const int64_t ni = m->n_interior_faces, nb = m->n_faces - m->n_interior_faces;
    /* the distinct cell labels */
    out->n_labels = 1;
    if (m->cell_region && m->n_cells > 0) {
        int32_t *v = malloc(sizeof(int32_t) * (size_t)m->n_cells);
        if (!v)
            return -1;
        memcpy(v, m->cell_region, sizeof(int32_t) * (size_t)m->n_cells);
        qsort(v, (size_t)m->n_cells, sizeof(int32_t), cmp_i32);
        int64_t n = 0;
        for (int64_t c = 0; c < m->n_cells; c++)
            if (c == 0 || v[c] != v[n - 1])
                v[n++] = v[c];
        out->n_labels = (int)n;
        out->label_value = v;
    }
    const int multi = out->n_labels > 1;
    /* per label: surface, the six walls, then the input's groups */
    const int ng = m->face_group ? m->n_groups : 0;
    const int per = N_KEYS + ng;
    const int nk = multi ? out->n_labels * per : per;
    int64_t *count = calloc((size_t)nk, sizeof(int64_t));
    int *id = malloc(sizeof(int) * (size_t)nk);
    out->face_patch = malloc(sizeof(int) * (size_t)(nb + 1));
    out->name = malloc(sizeof *out->name * (size_t)nk);
    out->size = malloc(sizeof(int64_t) * (size_t)nk);
    out->group = malloc(sizeof(int) * (size_t)nk);
    if (!count || !id || !out->face_patch || !out->name || !out->size || !out->group) {
        free(count);
        free(id);
        vc_boundary_patches_free(out);
        return -1;
    }
    for (int64_t f = ni; f < m->n_faces; f++) {
        int k = face_key(m, f);
        if (k == KEY_SURFACE && ng > 0 && m->face_group[f] >= 0 && m->face_group[f] < ng)
            k = N_KEYS + m->face_group[f];
        if (k < 0) {
            if (bad_face)
                *bad_face = f;
            free(count);
            free(id);
            vc_boundary_patches_free(out);
            return -2;
        }
        if (multi)
            k += per * vc_boundary_patches_label_rank(out, m->cell_region[m->face_owner[f]]);
        out->face_patch[f - ni] = k;
        count[k]++;
    }
    /* the patches that have faces, in key order */
    for (int k = 0; k < nk; k++) {
        id[k] = -1;
        if (!count[k])
            continue;
        id[k] = out->n_patches;
        const int kk = k % per;
        const char *base = kk < N_KEYS ? key_name[kk] : m->group_name[kk - N_KEYS];
        out->group[out->n_patches] = kk < N_KEYS ? -1 : kk - N_KEYS;
        if (multi)
            snprintf(out->name[out->n_patches], sizeof out->name[0], "region%d_%.50s",
                     (int)out->label_value[k / per], base);
        else
            snprintf(out->name[out->n_patches], sizeof out->name[0], "%s", base);
        out->size[out->n_patches] = count[k];
        out->n_patches++;
    }
    for (int64_t i = 0; i < nb; i++)
        out->face_patch[i] = id[out->face_patch[i]];
    free(count);
    free(id);
    return 0;
}
