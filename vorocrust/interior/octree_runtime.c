/* The p4est start-up the octree interior needs (see octree_runtime.h). */
#include "octree_runtime.h"

#include <mpi.h>
#include <p4est_base.h>

int vc_octree_runtime_available(void)
{
    int initialized = 0, finalized = 0;
    MPI_Initialized(&initialized);
    MPI_Finalized(&finalized);
    return initialized && !finalized;
}

int vc_octree_runtime_start(vc_error *err)
{
    int initialized = 0, finalized = 0;
    MPI_Initialized(&initialized);
    MPI_Finalized(&finalized);
    if (!initialized || finalized)
        return vc_error_set(err, VC_EPARAM,
                            "the octree interior needs MPI: the program must initialise MPI "
                            "before meshing (and finalise it after), or use the lattice "
                            "interior");
    /* p4est's own log lines silenced, once per process; the forests live
     * on MPI_COMM_SELF, so sc_init (MPI error handler, signal handlers) is
     * left to the program. */
    static int p4est_ready;
#pragma omp critical(vc_p4est_init)
    {
        if (!p4est_ready) {
            p4est_init(NULL, SC_LP_ERROR);
            p4est_ready = 1;
        }
    }
    return 0;
}
