/* Shared by the fuzz targets: the readers take a path, so each input is
 * written to one scratch file per process (in /dev/shm when it exists,
 * else $TMPDIR or /tmp) and read back from there. */
#ifndef VC_FUZZ_COMMON_H
#define VC_FUZZ_COMMON_H

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* Writes data to the scratch file "<dir>/vc-fuzz-<pid><suffix>"; returns
 * its path (a static buffer) or NULL. */
static const char *vc_fuzz_write(const uint8_t *data, size_t size, const char *suffix)
{
    static char path[512];
    if (!path[0] || !strstr(path, suffix)) {
        const char *dir = access("/dev/shm", W_OK) == 0 ? "/dev/shm" : getenv("TMPDIR");
        snprintf(path, sizeof path, "%s/vc-fuzz-%ld%s", dir ? dir : "/tmp", (long)getpid(), suffix);
    }
    FILE *f = fopen(path, "wb");
    if (!f)
        return NULL;
    if (size && fwrite(data, 1, size, f) != size) {
        fclose(f);
        return NULL;
    }
    if (fclose(f) != 0)
        return NULL;
    return path;
}

#endif
