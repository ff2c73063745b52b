/* MPI for the tests that build an octree interior: the library needs the
 * program to initialise MPI. Open MPI's start-up leaves allocations behind
 * on purpose, so the leak checker is off while it starts and stops
 * (tests/lsan.supp covers MPI's own threads). */
#ifndef VC_TEST_MPI_H
#define VC_TEST_MPI_H

#include <mpi.h>
#include <stdlib.h>

#if defined(__SANITIZE_ADDRESS__)
#include <sanitizer/lsan_interface.h>
#define TEST_LEAK_CHECK_OFF() __lsan_disable()
#define TEST_LEAK_CHECK_ON() __lsan_enable()
#else
#define TEST_LEAK_CHECK_OFF() ((void)0)
#define TEST_LEAK_CHECK_ON() ((void)0)
#endif

/* A lone process: no daemon, no network transports, no session directory
 * (shared by all isolated singletons and removed by the first to finish;
 * see apps/cli/mpi_session.c), as the CLI does. */
static inline int test_mpi_start(void)
{
    setenv("OMPI_MCA_ess_singleton_isolated", "1", 0);
    setenv("OMPI_MCA_orte_create_session_dirs", "0", 0);
    setenv("OMPI_MCA_pml", "ob1", 0);
    setenv("OMPI_MCA_btl", "self", 0);
    TEST_LEAK_CHECK_OFF();
    int rc = MPI_Init(NULL, NULL);
    TEST_LEAK_CHECK_ON();
    return rc == MPI_SUCCESS ? 0 : -1;
}

static inline void test_mpi_stop(void)
{
    TEST_LEAK_CHECK_OFF();
    MPI_Finalize();
    TEST_LEAK_CHECK_ON();
}

#endif
