/* MPI start and stop for the CLI (see mpi_session.h). */
#include "mpi_session.h"

#include <mpi.h>
#include <stdio.h>
#include <stdlib.h>

/* Open MPI's start-up leaves allocations behind on purpose (and unloads the
 * components that made them, so their stacks cannot be matched by a
 * suppression): under AddressSanitizer the leak checker is switched off
 * while MPI starts and stops (for this thread; tests/lsan.supp covers
 * MPI's own threads). */
#if defined(__SANITIZE_ADDRESS__)
#include <sanitizer/lsan_interface.h>
#define LEAK_CHECK_OFF() __lsan_disable()
#define LEAK_CHECK_ON() __lsan_enable()
#else
#define LEAK_CHECK_OFF() ((void)0)
#define LEAK_CHECK_ON() ((void)0)
#endif

static int we_started;

int vc_cli_mpi_start(void)
{
    int initialized = 0;
    MPI_Initialized(&initialized);
    if (initialized)
        return 0;
    /* A lone process (not launched by mpirun): Open MPI's singleton start
     * would otherwise spawn a daemon and probe the network transports
     * (about 0.3 s; 0.02 s with these). Isolated singletons all use one
     * session directory path (/tmp/ompi.HOST.UID/jf.0/1/0) and remove it at
     * MPI_Finalize, so a run that starts while another ends could fail
     * MPI_Init ("orte_session_dir failed", seen once in CI with two tests at
     * a time); nothing here needs the directory (no shared memory), so none
     * is made. The user's own settings win. */
    if (!getenv("OMPI_COMM_WORLD_SIZE")) {
        setenv("OMPI_MCA_ess_singleton_isolated", "1", 0);
        setenv("OMPI_MCA_orte_create_session_dirs", "0", 0);
        setenv("OMPI_MCA_pml", "ob1", 0);
        setenv("OMPI_MCA_btl", "self", 0);
    }
    LEAK_CHECK_OFF();
    int rc = MPI_Init(NULL, NULL);
    LEAK_CHECK_ON();
    if (rc != MPI_SUCCESS) {
        fprintf(stderr, "vorocrust: MPI_Init failed (error %d): the octree interior needs MPI; "
                "use --interior lattice\n", rc);
        return 1;
    }
    we_started = 1;
    return 0;
}

void vc_cli_mpi_stop(void)
{
    if (!we_started)
        return;
    int done = 0;
    MPI_Finalized(&done);
    if (!done) {
        LEAK_CHECK_OFF();
        MPI_Finalize();
        LEAK_CHECK_ON();
    }
    we_started = 0;
}
