/* libFuzzer target: the seeds CSV reader (vc_seeds_read_csv, as
 * `vorocrust voronoi SEEDS.csv` calls it). */
#include "vorocrust/seeds.h"
#include "fuzz_common.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    const char *path = vc_fuzz_write(data, size, ".csv");
    if (!path)
        return 0;
    vc_seeds s;
    vc_error err;
    memset(&err, 0, sizeof err);
    if (vc_seeds_read_csv(path, &s, &err) == 0)
        vc_seeds_free(&s);
    else if (!err.msg[0] || strchr(err.msg, '\n'))
        abort();
    return 0;
}
