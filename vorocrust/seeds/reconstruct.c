/* The reconstructed surface: the Voronoi facets between an inside and an
 * outside seed, taken from the conforming Voronoi mesh of the inside
 * seeds (the outside seeds are its non-kept seeds), so the facets share
 * the mesh's global vertices.
 *
 * The engine names every Voronoi vertex by its seeds, so both sides of the
 * degenerate edge between two ball centres (all the seeds of the triplets
 * sharing a pair of balls lie on one circle) list the same vertices. */
#include "vorocrust/sampling.h"
#include "vorocrust/voronoi.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void vc_polysurface_free(vc_polysurface *p)
{
    free(p->points);
    free(p->poly_offsets);
    free(p->poly_vertices);
    memset(p, 0, sizeof *p);
}

/* Is boundary face f of the surface: toward an outside seed among the
 * first n_surface (not the box, not a bounding seed)? */
static int on_surface(const vc_polymesh *m, int64_t f, int64_t n_surface)
{
    const int64_t o = m->face_other_seed[f];
    return o >= 0 && o < n_surface;
}

int vc_reconstruct_surface(const vc_seeds *seeds, int64_t n_surface,
                           const struct vc_seed_spheres *spheres, int threads,
                           const vc_logger *log, vc_polysurface *out, vc_error *err)
{
    memset(out, 0, sizeof *out);
    if (n_surface <= 0 || n_surface > seeds->n)
        n_surface = seeds->n;
    for (int64_t i = n_surface; i < seeds->n; i++)
        if (seeds->label[i] != 0)
            return vc_error_set(err, VC_EPARAM,
                                "bounding seed %lld has label %d: it must be 0 (not kept)",
                                (long long)i, (int)seeds->label[i]);
    vc_voronoi_options vo;
    vc_voronoi_options_default(&vo);
    vo.threads = threads;
    vo.log = log;
    vo.spheres = spheres;
    vc_polymesh m;
    int rc = vc_voronoi_build(seeds, &vo, &m, err);
    if (rc)
        return rc;
    int64_t nf = 0, nfv = 0;
    for (int64_t f = m.n_interior_faces; f < m.n_faces; f++)
        if (on_surface(&m, f, n_surface)) {
            nf++;
            nfv += m.face_offsets[f + 1] - m.face_offsets[f];
        }
    int64_t *newid = malloc(sizeof(int64_t) * (size_t)(m.n_points ? m.n_points : 1));
    out->poly_offsets = malloc(sizeof(int64_t) * (size_t)(nf + 1));
    out->poly_vertices = malloc(sizeof(int64_t) * (size_t)(nfv ? nfv : 1));
    if (!newid || !out->poly_offsets || !out->poly_vertices) {
        free(newid);
        vc_polysurface_free(out);
        vc_polymesh_free(&m);
        return vc_error_set(err, VC_ENOMEM, "out of memory for the reconstructed surface");
    }
    for (int64_t i = 0; i < m.n_points; i++)
        newid[i] = -1;
    int64_t np = 0, k = 0, q = 0;
    out->poly_offsets[0] = 0;
    for (int64_t f = m.n_interior_faces; f < m.n_faces; f++) {
        if (!on_surface(&m, f, n_surface))
            continue;
        for (int64_t j = m.face_offsets[f]; j < m.face_offsets[f + 1]; j++) {
            int64_t v = m.face_vertices[j];
            if (newid[v] < 0)
                newid[v] = np++;
            out->poly_vertices[k++] = newid[v];
        }
        out->poly_offsets[++q] = k;
    }
    out->n_polys = nf;
    out->n_points = np;
    out->points = malloc(sizeof(double) * 3 * (size_t)(np ? np : 1));
    if (!out->points) {
        free(newid);
        vc_polysurface_free(out);
        vc_polymesh_free(&m);
        return vc_error_set(err, VC_ENOMEM, "out of memory for the reconstructed surface");
    }
    for (int64_t i = 0; i < m.n_points; i++)
        if (newid[i] >= 0)
            memcpy(out->points + 3 * newid[i], m.points + 3 * i, sizeof(double) * 3);
    free(newid);
    vc_polymesh_free(&m);
    return 0;
}
