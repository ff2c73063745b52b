/* libFuzzer target: the surface readers (OBJ, OFF, STL, PLY) through
 * vc_surface_read, as `vorocrust info` and `mesh` call them (format
 * reader, soup validation, triangulation, vertex merging, surface check).
 * The first byte of the input picks the format (its value mod 4: obj, off,
 * stl, ply); the rest is the file. */
#include "vorocrust/surface.h"
#include "fuzz_common.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static const char *const ext[4] = {".obj", ".off", ".stl", ".ply"};
    if (size < 1)
        return 0;
    const char *path = vc_fuzz_write(data + 1, size - 1, ext[data[0] % 4]);
    if (!path)
        return 0;
    vc_surface s;
    vc_surface_report rep;
    vc_error err;
    memset(&err, 0, sizeof err);
    if (vc_surface_read(path, &s, &rep, &err) == 0)
        vc_surface_free(&s);
    else if (!err.msg[0] || strchr(err.msg, '\n'))
        abort(); /* every failure names its cause on one line */
    return 0;
}
