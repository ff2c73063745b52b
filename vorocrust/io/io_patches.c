/* The boundary patches for a writer (see io_patches.h). */
#include "io/io_patches.h"

#include <inttypes.h>

int vc_io_boundary_patches(const vc_polymesh *m, const char *path, vc_boundary_patches *bp,
                           vc_error *err)
{
    int64_t bad = -1;
    const int rc = vc_polymesh_boundary_patches(m, bp, &bad);
    if (rc == -1)
        return vc_error_set(err, VC_ENOMEM, "%s: out of memory", path);
    if (rc == -2)
        return vc_error_set(err, VC_EINPUT, "%s: boundary face %" PRId64 " has an unknown wall "
                            "code %" PRId64, path, bad, m->face_other_seed[bad]);
    return VC_OK;
}
