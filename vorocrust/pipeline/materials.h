/* Multi-material domains in the pipeline (thesis 6.2.2): the surface to
 * sample, the region of every seed, and the check of every region's cells
 * against the input's region. */
#ifndef VC_PIPELINE_MATERIALS_H
#define VC_PIPELINE_MATERIALS_H

#include <stdint.h>

#include "vorocrust/polymesh.h"
#include "vorocrust/regions.h"
#include "vorocrust/vorocrust.h"

typedef struct vc_materials {
    /* The input with every triangle once (a triangle given twice, reversed,
     * is one interface), and the regions on its triangles' two sides. */
    vc_surface surface;
    int64_t *side_region;   /* 2 per triangle: front, back; -1 unbounded */
    int64_t n_regions;
    int32_t *label;         /* per region: the label of its seeds and cells, region + 1,
                               or 0 for a void (a cavity: no cells) */
    double *volume;         /* per region, enclosed */
    int64_t *euler;         /* per region: Euler characteristic of its boundary */
    vc_region_locator *locator;
} vc_materials;

/* From the input s and its regions r. Returns 0, VC_ENOMEM. */
int vc_materials_init(const vc_surface *s, const vc_regions *r, vc_materials *m, vc_error *err);
void vc_materials_free(vc_materials *m);

/* Sets the label of seeds 0 .. n-1 to the label of the region that holds
 * it. Returns how many could not be located (on the surface, or every
 * segment from it grazed an edge): those get label 0. */
int64_t vc_materials_label_seeds(const vc_materials *m, vc_seeds *seeds, int64_t n, int threads);

/* Every material region's cells in mesh: their volume, and the faces
 * between them and other cells or the outside, oriented out of them, as a
 * surface whose topology is checked. Fills out (m->n_regions entries;
 * voids get label 0 and no cells) and the union of those faces, each once,
 * oriented out of the cell of the higher label, into surface. Returns 0,
 * VC_ENOMEM. */
int vc_materials_measure(const vc_materials *m, const vc_polymesh *mesh, vc_region_mesh *out,
                         vc_polysurface *surface, vc_error *err);

#endif
