/* A short spin for the OpenMP runtime's waiting threads (openmp_spin.c). */
#ifndef VC_CLI_OPENMP_SPIN_H
#define VC_CLI_OPENMP_SPIN_H

/* Unless the user set OMP_WAIT_POLICY or GOMP_SPINCOUNT: sets
 * GOMP_SPINCOUNT to VC_CLI_SPINCOUNT and runs this program again with the
 * same arguments (returns only when that fails; the run then goes on with
 * the runtime's default). */
void vc_cli_short_openmp_spin(char **argv);

#endif
