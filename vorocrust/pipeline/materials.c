/* Multi-material domains in the pipeline (see materials.h). */
#include "materials.h"

#include "util/threads.h"

#include <stdlib.h>
#include <string.h>

static int cmp_i64(const void *a, const void *b)
{
    const int64_t x = *(const int64_t *)a, y = *(const int64_t *)b;
    return (x > y) - (x < y);
}

void vc_materials_free(vc_materials *m)
{
    vc_region_locator_free(m->locator);
    vc_surface_free(&m->surface);
    free(m->side_region);
    free(m->label);
    free(m->volume);
    free(m->euler);
    memset(m, 0, sizeof *m);
}

int vc_materials_init(const vc_surface *s, const vc_regions *r, vc_materials *m, vc_error *err)
{
    memset(m, 0, sizeof *m);
    const int64_t nt = s->n_triangles, nr = r->n_regions;
    m->surface.xyz = malloc(sizeof(double) * 3 * (size_t)(s->n_vertices + 1));
    m->surface.tri = malloc(sizeof(int64_t) * 3 * (size_t)(nt + 1));
    m->side_region = malloc(sizeof(int64_t) * 2 * (size_t)(nt + 1));
    m->label = malloc(sizeof(int32_t) * (size_t)(nr + 1));
    m->volume = malloc(sizeof(double) * (size_t)(nr + 1));
    m->euler = calloc((size_t)nr + 1, sizeof(int64_t));
    /* (region, vertex) of every side, for the vertices of each boundary */
    int64_t *rv = malloc(sizeof(int64_t) * 6 * (size_t)(nt + 1));
    if (!m->surface.xyz || !m->surface.tri || !m->side_region || !m->label ||
        !m->volume || !m->euler || !rv)
        goto oom;
    memcpy(m->surface.xyz, s->xyz, sizeof(double) * 3 * (size_t)s->n_vertices);
    m->surface.n_vertices = s->n_vertices;
    /* the input's groups go along (their borders are creases) */
    if (s->tri_group && s->n_groups > 0) {
        m->surface.tri_group = malloc(sizeof(int32_t) * (size_t)(nt + 1));
        m->surface.group_name = malloc(sizeof *s->group_name * (size_t)s->n_groups);
        if (!m->surface.tri_group || !m->surface.group_name)
            goto oom;
        memcpy(m->surface.group_name, s->group_name, sizeof *s->group_name * (size_t)s->n_groups);
        m->surface.n_groups = s->n_groups;
    }
    int64_t n = 0, nrv = 0;
    for (int64_t t = 0; t < nt; t++) {
        /* a triangle given twice (reversed) is one interface: the first copy */
        if (r->first_copy[t] != t)
            continue;
        memcpy(m->surface.tri + 3 * n, s->tri + 3 * t, sizeof(int64_t) * 3);
        if (m->surface.tri_group)
            m->surface.tri_group[n] = s->tri_group[t];
        for (int side = 0; side < 2; side++) {
            const int64_t k = r->side_region[2 * t + side];
            m->side_region[2 * n + side] = k;
            if (k < 0)
                continue;
            m->euler[k]--; /* F/2 per side, as -1 per pair below */
            for (int j = 0; j < 3; j++)
                rv[nrv++] = k * (s->n_vertices + 1) + s->tri[3 * t + j];
        }
        n++;
    }
    m->surface.n_triangles = n;
    /* V - E + F with E = 3F/2 on a closed boundary: V - F/2 */
    for (int64_t k = 0; k < nr; k++) {
        if (m->euler[k] % 2) /* an odd side count: not closed, leave it to the check */
            m->euler[k] -= 1;
        m->euler[k] /= 2;
    }
    qsort(rv, (size_t)nrv, sizeof(int64_t), cmp_i64);
    for (int64_t i = 0; i < nrv; i++)
        if (i == 0 || rv[i] != rv[i - 1])
            m->euler[rv[i] / (s->n_vertices + 1)]++;
    m->n_regions = nr;
    for (int64_t k = 0; k < nr; k++) {
        m->label[k] = r->region[k].kind == VC_REGION_VOID ? 0 : (int32_t)(k + 1);
        m->volume[k] = r->region[k].volume;
    }
    free(rv);
    if (vc_region_locator_build(&m->surface, m->side_region, &m->locator, err)) {
        vc_materials_free(m);
        return VC_ENOMEM;
    }
    return 0;
oom:
    free(rv);
    vc_materials_free(m);
    return vc_error_set(err, VC_ENOMEM, "out of memory for the regions");
}

int64_t vc_materials_label_seeds(const vc_materials *m, vc_seeds *seeds, int64_t n, int threads)
{
    int64_t lost = 0;
    const int nth = vc_threads_or_default(threads);
    (void)nth;
#pragma omp parallel for schedule(dynamic, 256) reduction(+ : lost) num_threads(nth)
    for (int64_t i = 0; i < n; i++) {
        const int64_t k = vc_region_locate(m->locator, seeds->xyz + 3 * i);
        if (k == -2)
            lost++;
        seeds->label[i] = k >= 0 ? m->label[k] : 0;
    }
    return lost;
}

int vc_materials_measure(const vc_materials *m, const vc_polymesh *mesh, vc_region_mesh *out,
                         vc_polysurface *surface, vc_error *err)
{
    const int64_t nr = m->n_regions;
    memset(surface, 0, sizeof *surface);
    for (int64_t k = 0; k < nr; k++) {
        memset(&out[k], 0, sizeof out[k]);
        out[k].label = m->label[k];
        out[k].input_volume = m->volume[k];
        out[k].euler_input = m->euler[k];
    }
    /* label -> region: labels are region + 1 */
    for (int64_t c = 0; c < mesh->n_cells; c++) {
        const int32_t l = mesh->cell_region[c];
        if (l >= 1 && l <= nr) {
            out[l - 1].n_cells++;
            out[l - 1].mesh_volume += mesh->cell_volume[c];
        }
    }
    /* the faces between different labels */
    int64_t n_between = 0, n_slots = 0;
    for (int64_t f = 0; f < mesh->n_faces; f++) {
        const int32_t lo = mesh->cell_region[mesh->face_owner[f]];
        const int32_t ln = mesh->face_neighbour[f] >= 0 ? mesh->cell_region[mesh->face_neighbour[f]] : 0;
        if (lo == ln)
            continue;
        n_between++;
        n_slots += vc_polymesh_face_size(mesh, f);
        for (int side = 0; side < 2; side++) {
            const int32_t l = side ? ln : lo, other = side ? lo : ln;
            if (l >= 1 && l <= nr) {
                if (other == 0)
                    out[l - 1].n_boundary_faces++;
                else
                    out[l - 1].n_interface_faces++;
            }
        }
    }
    int64_t *map = malloc(sizeof(int64_t) * (size_t)(mesh->n_points + 1));
    int64_t *used = malloc(sizeof(int64_t) * (size_t)(n_slots + 1));
    vc_polysurface p;
    memset(&p, 0, sizeof p);
    p.points = malloc(sizeof(double) * 3 * (size_t)(n_slots + 1));
    p.poly_offsets = malloc(sizeof(int64_t) * (size_t)(n_between + 1));
    p.poly_vertices = malloc(sizeof(int64_t) * (size_t)(n_slots + 1));
    if (!map || !used || !p.points || !p.poly_offsets || !p.poly_vertices)
        goto oom;
    for (int64_t i = 0; i < mesh->n_points; i++)
        map[i] = -1;
    /* region k's surface, and with k = -1 the union, each in turn */
    for (int64_t k = -1; k < nr; k++) {
        if (k >= 0 && out[k].label == 0)
            continue;
        int64_t np = 0, nf = 0, ns = 0;
        p.poly_offsets[0] = 0;
        for (int64_t f = 0; f < mesh->n_faces; f++) {
            const int32_t lo = mesh->cell_region[mesh->face_owner[f]];
            const int32_t ln =
                mesh->face_neighbour[f] >= 0 ? mesh->cell_region[mesh->face_neighbour[f]] : 0;
            if (lo == ln)
                continue;
            int reversed;
            if (k < 0)
                reversed = ln > lo;
            else if (lo == k + 1)
                reversed = 0;
            else if (ln == k + 1)
                reversed = 1;
            else
                continue;
            const int64_t b = mesh->face_offsets[f], e = mesh->face_offsets[f + 1];
            for (int64_t j = 0; j < e - b; j++) {
                const int64_t v = mesh->face_vertices[reversed ? e - 1 - j : b + j];
                if (map[v] < 0) {
                    used[np] = v;
                    map[v] = np;
                    memcpy(p.points + 3 * np, mesh->points + 3 * v, sizeof(double) * 3);
                    np++;
                }
                p.poly_vertices[ns++] = map[v];
            }
            p.poly_offsets[++nf] = ns;
        }
        p.n_points = np;
        p.n_polys = nf;
        for (int64_t j = 0; j < np; j++) /* reset the map through the points used */
            map[used[j]] = -1;
        if (k < 0) {
            /* the union is kept: copy it out */
            surface->n_points = np;
            surface->n_polys = nf;
            surface->points = malloc(sizeof(double) * 3 * (size_t)(np + 1));
            surface->poly_offsets = malloc(sizeof(int64_t) * (size_t)(nf + 1));
            surface->poly_vertices = malloc(sizeof(int64_t) * (size_t)(ns + 1));
            if (!surface->points || !surface->poly_offsets || !surface->poly_vertices)
                goto oom;
            memcpy(surface->points, p.points, sizeof(double) * 3 * (size_t)np);
            memcpy(surface->poly_offsets, p.poly_offsets, sizeof(int64_t) * (size_t)(nf + 1));
            memcpy(surface->poly_vertices, p.poly_vertices, sizeof(int64_t) * (size_t)ns);
            continue;
        }
        int rc = vc_polysurface_topology_compute(&p, &out[k].topology, err);
        if (rc) {
            free(map);
            free(used);
            vc_polysurface_free(&p);
            vc_polysurface_free(surface);
            return rc;
        }
        const vc_polysurface_topology *t = &out[k].topology;
        out[k].closed = !t->n_boundary_edges && !t->n_nonmanifold_edges &&
                        !t->n_misoriented_edges && !t->n_nonmanifold_vertices &&
                        t->euler == out[k].euler_input;
    }
    free(map);
    free(used);
    vc_polysurface_free(&p);
    return 0;
oom:
    free(map);
    free(used);
    vc_polysurface_free(&p);
    vc_polysurface_free(surface);
    return vc_error_set(err, VC_ENOMEM, "out of memory measuring the regions");
}
