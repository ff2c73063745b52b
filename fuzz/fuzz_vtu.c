/* libFuzzer target: the .vtu reader (vc_vtu_read, as `vorocrust quality`
 * and `compare` call it). */
#include "vorocrust/vtu_reader.h"
#include "fuzz_common.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    const char *path = vc_fuzz_write(data, size, ".vtu");
    if (!path)
        return 0;
    vc_vtu_mesh m;
    vc_error err;
    memset(&err, 0, sizeof err);
    if (vc_vtu_read(path, &m, &err) == 0)
        vc_vtu_mesh_free(&m);
    else if (!err.msg[0] || strchr(err.msg, '\n'))
        abort();
    return 0;
}
