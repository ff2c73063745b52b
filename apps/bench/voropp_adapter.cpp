// Thin C++ adapter around Voro++ for the Voronoi benchmark: computes every
// cell of n seeds in a non-periodic box, with neighbour tracking on (the
// fair comparison: vorocrust also builds the connectivity), and returns
// totals that can be checked against vorocrust's mesh.
#include "voropp_adapter.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <new>
#include <vector>

#include <voro++.hh>

extern "C" int vc_bench_voropp(const double *xyz, int64_t n, const double box[6],
                               vc_bench_voropp_result *res, char *msg, size_t msg_len)
{
    *res = vc_bench_voropp_result();
    if (n <= 0 || n > INT32_MAX) {
        std::snprintf(msg, msg_len, "Voro++: unsupported seed count %lld", (long long)n);
        return 1;
    }
    try {
        // A block grid with about 5 particles per block, shaped like the box.
        const double lx = box[3] - box[0], ly = box[4] - box[1], lz = box[5] - box[2];
        const double h = std::cbrt(5.0 * lx * ly * lz / (double)n);
        const int nx = std::max(1, (int)std::lround(lx / h));
        const int ny = std::max(1, (int)std::lround(ly / h));
        const int nz = std::max(1, (int)std::lround(lz / h));
        voro::container con(box[0], box[3], box[1], box[4], box[2], box[5], nx, ny, nz,
                            false, false, false, 8);
        for (int64_t i = 0; i < n; i++)
            con.put((int)i, xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]);
        if (con.total_particles() != (int)n) {
            std::snprintf(msg, msg_len, "Voro++: only %d of %lld seeds inside the box",
                          con.total_particles(), (long long)n);
            return 1;
        }

        voro::voronoicell_neighbor cell;
        voro::c_loop_all loop(con);
        std::vector<int> neigh;
        double volume = 0.0;
        int64_t cells = 0, cell_faces = 0, wall_faces = 0;
        if (loop.start()) {
            do {
                if (!con.compute_cell(cell, loop))
                    continue;
                cells++;
                volume += cell.volume();
                cell_faces += cell.number_of_faces();
                cell.neighbors(neigh);
                for (int id : neigh)
                    wall_faces += id < 0;
            } while (loop.inc());
        }
        res->volume = volume;
        res->cells = cells;
        res->cell_faces = cell_faces;
        res->boundary_faces = wall_faces;
        res->grid[0] = nx;
        res->grid[1] = ny;
        res->grid[2] = nz;
    } catch (const std::bad_alloc &) {
        std::snprintf(msg, msg_len, "Voro++: out of memory for %lld seeds", (long long)n);
        return 1;
    } catch (...) {
        std::snprintf(msg, msg_len, "Voro++: unexpected exception");
        return 1;
    }
    return 0;
}
