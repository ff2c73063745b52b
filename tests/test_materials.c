/* Tests of the multi-material checks (pipeline/materials.h): the regions
 * of a row of boxes read off the Voronoi mesh of lattice seeds labelled by
 * the region locator. With the lattice's bisectors on the boxes' faces,
 * every region's cells hold exactly its volume and are bounded by a
 * closed sphere-like surface; one cell given the wrong region breaks both
 * regions' topology, which vc_materials_measure must report. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "pipeline/materials.h"
#include "vorocrust/voronoi.h"

#include "test_check.h"
#include "test_surface_util.h"

int main(void)
{
    builder b = {0};
    box_row(&b, 2, 2);
    vc_error err = {0, ""};
    vc_regions r;
    CHECK_MSG(vc_surface_regions(&b.s, &r, &err) == 0, err.msg);
    vc_materials mm;
    CHECK_MSG(vc_materials_init(&b.s, &r, &mm, &err) == 0, err.msg);
    CHECK(mm.n_regions == 2 && mm.euler[0] == 2 && mm.euler[1] == 2);
    CHECK(fabs(mm.volume[0] - 1) < 1e-12 && fabs(mm.volume[1] - 1) < 1e-12);

    /* seeds at the centres of 0.1 cubes over [-0.4, 2.4] x [-0.4, 1.4]^2 */
    const int nx = 28, ny = 18, nz = 18;
    vc_seeds seeds;
    CHECK(vc_seeds_alloc(&seeds, (int64_t)nx * ny * nz, &err) == 0);
    int64_t n = 0;
    for (int k = 0; k < nz; k++)
        for (int j = 0; j < ny; j++)
            for (int i = 0; i < nx; i++) {
                double *p = seeds.xyz + 3 * n++;
                p[0] = -0.35 + 0.1 * i;
                p[1] = -0.35 + 0.1 * j;
                p[2] = -0.35 + 0.1 * k;
            }
    CHECK(vc_materials_label_seeds(&mm, &seeds, seeds.n, 2) == 0);
    int64_t in_region[3] = {0, 0, 0};
    for (int64_t i = 0; i < seeds.n; i++)
        in_region[seeds.label[i]]++;
    CHECKF(in_region[1] == 1000 && in_region[2] == 1000, "seeds per region %lld %lld",
           (long long)in_region[1], (long long)in_region[2]);

    vc_voronoi_options vo;
    vc_voronoi_options_default(&vo);
    vo.threads = 2;
    vc_polymesh m;
    CHECK_MSG(vc_voronoi_build(&seeds, &vo, &m, &err) == 0, err.msg);
    vc_region_mesh rm[2];
    vc_polysurface surf;
    CHECK_MSG(vc_materials_measure(&mm, &m, rm, &surf, &err) == 0, err.msg);
    for (int k = 0; k < 2; k++) {
        CHECKF(rm[k].label == k + 1 && rm[k].n_cells == 1000 && rm[k].closed &&
                   fabs(rm[k].mesh_volume - 1) < 1e-9,
               "region %d: label %d, %lld cells, closed %d, volume %.17g", k + 1, rm[k].label,
               (long long)rm[k].n_cells, rm[k].closed, rm[k].mesh_volume);
        /* a unit box: 10 x 10 squares per face, one face shared */
        CHECKF(rm[k].n_boundary_faces == 500 && rm[k].n_interface_faces == 100,
               "region %d: %lld boundary, %lld interface faces", k + 1,
               (long long)rm[k].n_boundary_faces, (long long)rm[k].n_interface_faces);
    }
    CHECK(surf.n_polys == 1100);
    vc_polysurface_free(&surf);

    /* a cell in the middle of region 1 labelled 2: both regions' faces
     * gain a separate sphere (Euler characteristic 4, not 2) */
    int64_t mid = -1;
    for (int64_t c = 0; c < m.n_cells; c++) {
        const double *s = seeds.xyz + 3 * m.cell_seed[c];
        if (fabs(s[0] - 0.45) < 1e-9 && fabs(s[1] - 0.45) < 1e-9 && fabs(s[2] - 0.45) < 1e-9)
            mid = c;
    }
    CHECK(mid >= 0);
    if (mid >= 0) {
        m.cell_region[mid] = 2;
        CHECK_MSG(vc_materials_measure(&mm, &m, rm, &surf, &err) == 0, err.msg);
        CHECKF(!rm[0].closed && rm[0].topology.euler == 4 && !rm[1].closed &&
                   rm[1].topology.euler == 4,
               "a misplaced cell: closed %d %d, euler %lld %lld", rm[0].closed, rm[1].closed,
               (long long)rm[0].topology.euler, (long long)rm[1].topology.euler);
        vc_polysurface_free(&surf);
    }
    printf("two boxes: 2 x 1000 cells, volumes exact, faces closed; a misplaced cell caught\n");
    vc_polymesh_free(&m);
    vc_seeds_free(&seeds);
    vc_materials_free(&mm);
    vc_regions_free(&r);
    vc_surface_free(&b.s);
    return failures ? 1 : 0;
}
