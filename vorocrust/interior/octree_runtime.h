/* The MPI and p4est start-up the octree interior needs (p4est is built
 * with MPI). Internal to vorocrust/interior. */
#ifndef VC_INTERIOR_OCTREE_RUNTIME_H
#define VC_INTERIOR_OCTREE_RUNTIME_H

#include "vorocrust/error.h"

/* Initialises MPI (unless the program already did) and the sc and p4est
 * libraries with their logging silenced, once per process; registers their
 * finalisation at exit. Call from the main thread. Fails with
 * VC_EINTERNAL when MPI cannot start. */
int vc_octree_runtime_start(vc_error *err);

#endif
