/* Files and directories in the C unit tests that write output: counting a
 * directory's entries, reading a file back whole. */
#ifndef VC_TEST_FILE_UTIL_H
#define VC_TEST_FILE_UTIL_H

#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Number of entries of dir (not "." and "..") whose name contains part
 * (every entry when part is NULL); -1 when dir cannot be opened. */
static inline int count_dir_entries(const char *dir, const char *part)
{
    DIR *d = opendir(dir);
    if (!d)
        return -1;
    int n = 0;
    struct dirent *e;
    while ((e = readdir(d)) != NULL)
        if (strcmp(e->d_name, ".") && strcmp(e->d_name, "..") && (!part || strstr(e->d_name, part)))
            ++n;
    closedir(d);
    return n;
}

/* The whole file, NUL-terminated (free it), its size in *size when size
 * is not NULL; NULL when it cannot be opened or read in full. */
static inline char *read_file_bytes(const char *path, size_t *size)
{
    FILE *fp = fopen(path, "rb");
    if (!fp)
        return NULL;
    fseek(fp, 0, SEEK_END);
    long n = ftell(fp);
    fseek(fp, 0, SEEK_SET);
    char *s = malloc((size_t)n + 1);
    if (s && fread(s, 1, (size_t)n, fp) != (size_t)n) {
        free(s);
        s = NULL;
    }
    if (s) {
        s[n] = 0;
        if (size)
            *size = (size_t)n;
    }
    fclose(fp);
    return s;
}

/* A text file as a string (free it), or NULL. */
static inline char *read_file_text(const char *path)
{
    return read_file_bytes(path, NULL);
}

#endif
