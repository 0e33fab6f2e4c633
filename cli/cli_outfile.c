/* Output files written safely (see cli_outfile.h). */
#define _XOPEN_SOURCE 700
#include "cli/cli_outfile.h"
#include "cli/cli_args.h"
#include "cli/cli_output.h"
#include "cli/exit_codes.h"

#include <errno.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* A command writes at most a picture and its script at once; batch and horizon one file. */
#define SLOTS 4
#define TMP_PATH_MAX 4096

static char tmp_paths[SLOTS][TMP_PATH_MAX];
static volatile sig_atomic_t tmp_live[SLOTS];

static void on_signal(int sig)
{
    for (int i = 0; i < SLOTS; ++i)
        if (tmp_live[i]) unlink(tmp_paths[i]);
    signal(sig, SIG_DFL);
    raise(sig);
}

/* A signal ignored on entry (nohup, trap '') stays ignored: the user asked for that. */
static void guard_signal(int sig)
{
    struct sigaction old;
    if (sigaction(sig, NULL, &old) == 0 && old.sa_handler == SIG_IGN) return;
    if (old.sa_handler == on_signal) return;
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    sigemptyset(&sa.sa_mask);
    sigaction(sig, &sa, NULL);
}

void cli_input_of(cli_input *in, const char *what, const char *path)
{
    struct stat st;
    memset(in, 0, sizeof *in);
    in->what = what;
    in->path = path;
    if (path && strcmp(path, "-") == 0) {
        in->path = "<stdin>";
        if (fstat(STDIN_FILENO, &st) == 0 && S_ISREG(st.st_mode)) {
            in->dev = st.st_dev;
            in->ino = st.st_ino;
            in->known = 1;
        }
    } else if (path && stat(path, &st) == 0) {
        in->dev = st.st_dev;
        in->ino = st.st_ino;
        in->known = 1;
    }
}

int cli_out_allowed(const char *cmd, const char *opt, const char *path, const cli_input *in, int n)
{
    struct stat st;
    /* An empty name (an unset shell variable) used to pass here as "does not exist", run the
     * whole job into "OUT.partial-XXXXXX" beside the current directory and fail at the
     * rename. */
    if (!*path) return cli_fail(CLI_EXIT_CANTCREAT, cmd, "%s '': an empty file name", opt);
    /* '-' is standard output only where a command says so (batch); here it was created as a
     * file named '-' in the current directory, and the run said nothing. */
    if (strcmp(path, "-") == 0)
        return cli_fail(CLI_EXIT_USAGE, cmd,
                        "%s -: this output cannot be standard output; name a file", opt);
    if (lstat(path, &st) != 0) {
        if (errno == ENOENT) return 0;
        return cli_fail(CLI_EXIT_CANTCREAT, cmd, "%s %s: %s", opt, path, strerror(errno));
    }
    if (S_ISLNK(st.st_mode))
        return cli_fail(CLI_EXIT_CANTCREAT, cmd,
                        "%s %s is a symbolic link: refused (name the file itself)", opt, path);
    if (S_ISDIR(st.st_mode))
        return cli_fail(CLI_EXIT_CANTCREAT, cmd, "%s %s is a directory, not a file", opt, path);
    if (!S_ISREG(st.st_mode))
        return cli_fail(CLI_EXIT_CANTCREAT, cmd,
                        "%s %s exists and is not a regular file (a device, FIFO or socket): "
                        "refused",
                        opt, path);
    for (int i = 0; i < n; ++i)
        if (in[i].known && in[i].dev == st.st_dev && in[i].ino == st.st_ino)
            return cli_fail(CLI_EXIT_CANTCREAT, cmd, "%s %s is the %s %s: refused", opt, path,
                            in[i].what, in[i].path);
    return 0;
}

int cli_stdout_not_input(const char *cmd, const char *what, const char *name, int fd,
                         const char *path)
{
    struct stat in, out;
    if (fstat(STDOUT_FILENO, &out) != 0 || !S_ISREG(out.st_mode)) return 0;
    if ((fd >= 0 ? fstat(fd, &in) : path ? stat(path, &in) : -1) != 0) return 0;
    if (in.st_dev != out.st_dev || in.st_ino != out.st_ino) return 0;
    return cli_fail(CLI_EXIT_CANTCREAT, cmd,
                    "standard output is the %s %s: refused (it would be written into)", what, name);
}

/* The directory part of path ("." when it has none) into buf, and the name after it. */
static const char *split_dir(const char *path, char *buf, size_t cap)
{
    const char *slash = strrchr(path, '/');
    if (!slash) {
        snprintf(buf, cap, ".");
        return path;
    }
    size_t n = slash == path ? 1 : (size_t)(slash - path);
    snprintf(buf, cap, "%.*s", n < cap ? (int)n : (int)cap - 1, path);
    return slash + 1;
}

int cli_outputs_distinct(const char *cmd, const char *opt_a, const char *a, const char *opt_b,
                         const char *b)
{
    if (!a || !b) return 0;
    int same = strcmp(a, b) == 0;
    if (!same) {
        char da[TMP_PATH_MAX], db[TMP_PATH_MAX];
        const char *na = split_dir(a, da, sizeof da), *nb = split_dir(b, db, sizeof db);
        struct stat sa, sb;
        same = strcmp(na, nb) == 0 && stat(da, &sa) == 0 && stat(db, &sb) == 0 &&
               sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
    }
    if (!same) return 0;
    return cli_fail(CLI_EXIT_USAGE, cmd, "%s %s and %s %s name the same file: give two names",
                    opt_a, a, opt_b, b);
}

int cli_out_open(cli_out *o, const char *cmd, const char *opt, const char *path,
                 const cli_input *in, int n)
{
    memset(o, 0, sizeof *o);
    o->slot = -1;
    int rc = cli_out_allowed(cmd, opt, path, in, n);
    if (rc) return rc;
    int slot = 0;
    while (slot < SLOTS && tmp_live[slot]) ++slot;
    if (slot == SLOTS) return cli_fail(CLI_EXIT_SOFTWARE, cmd, "too many output files at once");
    char *tmp = tmp_paths[slot];
    int len = snprintf(tmp, TMP_PATH_MAX, "%s.partial-XXXXXX", path);
    if (len < 0 || len >= TMP_PATH_MAX)
        return cli_fail(CLI_EXIT_CANTCREAT, cmd, "%s %s: path too long", opt, path);
    guard_signal(SIGINT);
    guard_signal(SIGTERM);
    guard_signal(SIGHUP);
    int fd = mkstemp(tmp);
    if (fd < 0)
        return cli_fail(CLI_EXIT_CANTCREAT, cmd, "%s %s: cannot create: %s", opt, path,
                        strerror(errno));
    tmp_live[slot] = 1;
    /* mkstemp makes the file private (0600); the result gets the usual mode. */
    mode_t mask = umask(0);
    umask(mask);
    (void)fchmod(fd, 0666 & ~mask);
    o->f = fdopen(fd, "w");
    if (!o->f) {
        int er = errno;
        close(fd);
        unlink(tmp);
        tmp_live[slot] = 0;
        return cli_fail(CLI_EXIT_CANTCREAT, cmd, "%s %s: %s", opt, path, strerror(er));
    }
    o->path = path;
    o->opt = opt;
    o->slot = slot;
    return 0;
}

const char *cli_out_temp(const cli_out *o) { return o->slot >= 0 ? tmp_paths[o->slot] : NULL; }

static void release(cli_out *o)
{
    if (o->slot < 0) return;
    unlink(tmp_paths[o->slot]);
    tmp_live[o->slot] = 0;
    o->slot = -1;
}

int cli_out_commit(cli_out *o, const char *cmd)
{
    if (o->slot < 0) return cli_fail(CLI_EXIT_SOFTWARE, cmd, "output committed twice");
    const char *tmp = tmp_paths[o->slot];
    int rc = 0;
    if (o->f) {
        /* One line whatever fails first, naming the file the user asked for (the temporary
         * name is ours). */
        rc = cli_flush_output(o->f, o->path, cmd);
        if (rc == 0 && fsync(fileno(o->f)) != 0)
            rc = cli_fail(CLI_EXIT_IOERR, cmd, "cannot write %s: %s", o->path, strerror(errno));
        if (rc == 0) rc = cli_close_output(o->f, o->path, cmd);
        else fclose(o->f);
        o->f = NULL;
    }
    /* The path may have changed while we wrote: check it again just before the rename. */
    if (rc == 0) rc = cli_out_allowed(cmd, o->opt, o->path, NULL, 0);
    if (rc == 0 && rename(tmp, o->path) != 0)
        rc = cli_fail(CLI_EXIT_IOERR, cmd, "cannot rename %s to %s: %s", tmp, o->path,
                      strerror(errno));
    if (rc == 0) tmp_live[o->slot] = 0, o->slot = -1;
    else release(o);
    return rc;
}

void cli_out_abandon(cli_out *o)
{
    if (o->f) fclose(o->f);
    o->f = NULL;
    release(o);
}
