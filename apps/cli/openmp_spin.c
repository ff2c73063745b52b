/* libgomp's waiting threads spin for up to 300,000 iterations at a barrier
 * before they sleep (its default without OMP_WAIT_POLICY). When another
 * process shares the cores, the spinning threads hold the cores the
 * threads they wait for need, and the sampler, which meets a barrier every
 * batch of 256 darts, crawls: two meshes of the same 42k-triangle surface
 * run at once on this 2-core machine took 27 s each, against 8.6 to 9.5 s
 * with a spin of 10,000 and 5.1 s alone; alone the short spin costs 1.5%
 * (bunny.off 4.51-4.57 s to 4.63 s). The ctest suite runs two tests at
 * once, as a user's batch script would. libgomp reads its environment when
 * it is loaded, before main: the setting takes a fresh start of the
 * program, once (the variable is then set). Under valgrind, set either
 * variable: the fresh start would leave the tool. */
#include "openmp_spin.h"

#include <stdlib.h>
#include <unistd.h>

#define VC_CLI_SPINCOUNT "10000"

void vc_cli_short_openmp_spin(char **argv)
{
    if (getenv("OMP_WAIT_POLICY") || getenv("GOMP_SPINCOUNT"))
        return;
    if (setenv("GOMP_SPINCOUNT", VC_CLI_SPINCOUNT, 1) != 0)
        return;
    execv("/proc/self/exe", argv);
}
