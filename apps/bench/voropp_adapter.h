/* The benchmark's C view of Voro++ (voropp_adapter.cpp). */
#ifndef VC_BENCH_VOROPP_ADAPTER_H
#define VC_BENCH_VOROPP_ADAPTER_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct vc_bench_voropp_result {
    double volume;          /* sum of the cell volumes */
    int64_t cells;          /* cells computed */
    int64_t cell_faces;     /* sum over cells of their face count (an interior
                               face counts twice, once per side) */
    int64_t boundary_faces; /* of which on the box walls */
    int grid[3];            /* Voro++ block grid used */
} vc_bench_voropp_result;

/* Computes the Voronoi cells of the n seeds xyz (3*n doubles) in the box
 * [box[0],box[3]] x [box[1],box[4]] x [box[2],box[5]] with Voro++
 * (non-periodic container, voronoicell_neighbor). Returns 0, or non-zero
 * with a message in msg. Single-threaded. */
int vc_bench_voropp(const double *xyz, int64_t n, const double box[6],
                    vc_bench_voropp_result *res, char *msg, size_t msg_len);

#ifdef __cplusplus
}
#endif
#endif
