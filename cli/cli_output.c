/* Checked output (see cli_output.h). */
#define _POSIX_C_SOURCE 200809L
#include "cli/cli_output.h"
#include "cli/exit_codes.h"

#include <errno.h>
#include <fcntl.h>
#include <string.h>
#include <unistd.h>

void cli_guard_std_fds(void)
{
    for (int fd = 0; fd <= 2; ++fd) {
        if (fcntl(fd, F_GETFD) != -1 || errno != EBADF) continue;
        /* open() returns the lowest free descriptor: this one. Read-only for 1 and 2 (writes
         * fail with EBADF), write-only for 0 (reads fail). */
        int got = open("/dev/null", fd == 0 ? O_WRONLY : O_RDONLY);
        if (got != fd && got >= 0) close(got);
    }
}

/* Why a write by cli_put_line to stdout failed (0: none did): a text larger than stdio's
 * buffer is written out during the call, and the stream then drops what it held, so the
 * final flush succeeds with no errno to name. */
static int stdout_errno;

void cli_put_line(const char *s)
{
    size_t n = strlen(s);
    errno = 0;
    if ((fwrite(s, 1, n, stdout) < n || putchar('\n') == EOF) && !stdout_errno)
        stdout_errno = errno;
}

static int failed(const char *what, const char *cmd, int err)
{
    fprintf(stderr, "headplan %s: cannot write %s: %s\n", cmd, what,
            err ? strerror(err) : "write error");
    return CLI_EXIT_IOERR;
}

int cli_flush_output(FILE *f, const char *what, const char *cmd)
{
    errno = 0;
    int bad = fflush(f) != 0;
    int err = bad ? errno : 0;
    if (!err && f == stdout) err = stdout_errno;
    if (bad || ferror(f)) return failed(what, cmd, err);
    return 0;
}

int cli_close_output(FILE *f, const char *what, const char *cmd)
{
    int rc = cli_flush_output(f, what, cmd);
    errno = 0;
    if (fclose(f) != 0 && rc == 0) rc = failed(what, cmd, errno);
    return rc;
}

int cli_finish_stdout(const char *cmd, int status)
{
    int rc = cli_close_output(stdout, "standard output", cmd);
    if (rc == 0) return status;
    return status == CLI_EXIT_OK || status == CLI_EXIT_CLOSEST ? rc : status;
}
