/* The repair passes the Voronoi engine runs on a mesh whose stitching met
 * a degeneracy (internal to the library; see repair_degenerate in
 * voronoi/voronoi_build.c). Each runs on threads threads (>= 1; the result
 * does not depend on it). */
#ifndef VC_POLYMESH_REPAIR_H
#define VC_POLYMESH_REPAIR_H

#include <stdint.h>

#include "vorocrust/polymesh.h"

/* Closes open cells by collapsing tiny clusters of points: for every cell
 * that does not use each of its edges exactly once each way, the points
 * of that cell within rel_radius times its size (the largest distance from
 * its centroid to a vertex) of an end of such an edge are merged into one
 * (the lowest index, whose position is kept; merging is transitive).
 * Nearly co-spherical seeds make clusters of Voronoi vertices a few merge
 * tolerances wide whose micro-edges two neighbouring cells can resolve
 * differently; at that scale they are one vertex (the engine uses
 * rel_radius 1e-6: clusters up to 2.1e-7 of the cell size wide were
 * measured). Faces left with fewer than 3 points are dropped, points no face
 * uses any more removed (order kept), and the geometry of the changed
 * faces and cells recomputed. Returns the number of points merged away,
 * or -1 when out of memory (the mesh is then still valid, possibly with
 * unused points). */
int64_t vc_polymesh_collapse_open_clusters(vc_polymesh *m, double rel_radius, int threads);

/* Drops the faces a cell lists twice: two faces of one cell with the same
 * cycle in the same direction (the cell then uses each of its edges twice
 * one way). Nearly co-spherical seeds (within a few merge tolerances of
 * one sphere, not on it) make clusters of Voronoi vertices a few merge
 * tolerances wide, where the faces of three cells can collapse onto one
 * triangle: one cell lists it for each of two neighbours, and in one of
 * those neighbours it hangs by its points alone (no other face of that
 * cell holds the reverse of one of its edges). That copy is removed from
 * both its cells, which closes all three. Where neither or both copies
 * hang so, nothing is changed. Points no face uses any more are dropped
 * (order kept) and the geometry of the changed cells recomputed. Returns
 * the number of faces dropped, or -1 when out of memory (the mesh is then
 * still valid, possibly with unused points). */
int64_t vc_polymesh_drop_duplicate_faces(vc_polymesh *m, int threads);

/* Removes the straight vertices: a vertex with exactly two neighbours in
 * the edge graph of the whole mesh lies inside an edge (every face that
 * holds it holds the path a - v - b; in closed convex cells such a path is
 * straight), so it is taken out of every face, which keeps every cell
 * closed and every face the same polygon. Degenerate Voronoi vertices
 * leave such points: four seeds on one circle (VoroCrust makes them for
 * every pair of overlapping balls) computed in floating point have their
 * circumcentre somewhere on the circle's axis, a true Voronoi vertex of the
 * rounded seeds where only a zero-width face starts, which the stitching
 * drops; and the stitching's T-junction repair inserts points into edges.
 * A vertex is kept where removing it would leave a face with fewer than 3
 * vertices. Points are renumbered (order kept) and the geometry of the
 * changed faces and their cells recomputed. Returns the number of
 * vertices removed, or -1 when out of memory (the mesh is then unchanged). */
int64_t vc_polymesh_remove_straight_vertices(vc_polymesh *m, int threads);

#endif
