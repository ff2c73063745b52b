/* The process umask, for files and directories the writers create with
 * restrictive modes (mkstemp, mkdtemp) and then open up to what an ordinary
 * creation would give. Internal to vorocrust/io. */
#ifndef VC_IO_FILE_MODE_H
#define VC_IO_FILE_MODE_H

#include <sys/types.h>

/* Linux reports the umask in /proc/self/status; elsewhere it can only be
 * read by setting it (briefly changing it for the whole process), so that
 * is the fallback. */
mode_t vc_io_umask(void);

#endif
