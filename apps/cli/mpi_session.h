/* MPI for the commands that mesh with the octree interior: the library
 * needs MPI initialised by its caller (vorocrust/vorocrust.h). */
#ifndef VC_CLI_MPI_SESSION_H
#define VC_CLI_MPI_SESSION_H

/* Initialises MPI unless it already is; returns 0, or prints one line and
 * returns 1. */
int vc_cli_mpi_start(void);

/* Finalises MPI if vc_cli_mpi_start initialised it. */
void vc_cli_mpi_stop(void);

#endif
