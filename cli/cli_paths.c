/* The installed folders are found from the program's own path (/proc/self/exe), not from
 * the prefix the build was configured with: `cmake --install --prefix DIR` and a package
 * may put the program anywhere, and the help must name files that exist there. */
#define _POSIX_C_SOURCE 200809L
#include "cli/cli_paths.h"

#include <limits.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#ifndef PATH_MAX
#define PATH_MAX 4096
#endif

/* out = PREFIX/rel when this program is PREFIX/bin/NAME and PREFIX/rel/probe is readable;
 * else out = fallback. */
static void installed(const char *rel, const char *probe, const char *fallback, char *out, size_t n)
{
    char exe[PATH_MAX];
    ssize_t len = readlink("/proc/self/exe", exe, sizeof exe - 1);
    snprintf(out, n, "%s", fallback);
    if (len <= 0) return;
    exe[len] = '\0';
    char *slash = strrchr(exe, '/');
    if (!slash) return;
    *slash = '\0'; /* the program's folder */
    slash = strrchr(exe, '/');
    if (!slash || strcmp(slash, "/bin") != 0) return;
    *slash = '\0'; /* the prefix ("" for a program in /bin) */
    char path[PATH_MAX + 64], test[PATH_MAX + 128];
    int k = snprintf(path, sizeof path, "%s/%s", exe, rel);
    if (k < 0 || (size_t)k >= sizeof path || (size_t)k >= n) return;
    k = snprintf(test, sizeof test, "%s/%s", path, probe);
    if (k < 0 || (size_t)k >= sizeof test || access(test, R_OK) != 0) return;
    snprintf(out, n, "%s", path);
}

const char *cli_doc_dir(void)
{
    static char dir[PATH_MAX + 64];
    if (!dir[0]) installed("share/doc/headplan/docs", "scenes.md", "docs", dir, sizeof dir);
    return dir;
}

const char *cli_scene_dir(void)
{
    static char dir[PATH_MAX + 64];
    if (!dir[0])
        installed("share/headplan/scenarios", "default.yaml", "scenarios", dir, sizeof dir);
    return dir;
}
