/* The boundary patches for a writer, its errors naming the file (internal
 * to the io module). */
#ifndef VC_IO_PATCHES_H
#define VC_IO_PATCHES_H

#include "vorocrust/error.h"
#include "vorocrust/polymesh.h"

/* vc_polymesh_boundary_patches into *bp; VC_ENOMEM or VC_EINPUT (a face on
 * an unknown wall) with a message naming path. */
int vc_io_boundary_patches(const vc_polymesh *m, const char *path, vc_boundary_patches *bp,
                           vc_error *err);

#endif
