/* The p4est start-up the octree interior needs (p4est is built with MPI).
 * Internal to the library. */
#ifndef VC_INTERIOR_OCTREE_RUNTIME_H
#define VC_INTERIOR_OCTREE_RUNTIME_H

#include "vorocrust/error.h"

/* Checks that the program has initialised MPI (the library never starts
 * or stops it) and initialises p4est with its logging silenced, once per
 * process. Fails with VC_EPARAM when MPI is not initialised, or already
 * finalised. */
int vc_octree_runtime_start(vc_error *err);

/* Whether MPI is initialised and not finalised: the octree can run. */
int vc_octree_runtime_available(void);

#endif
