/* cli/sha256.c (Nettle behind the batch metadata's interface) against the known answers of
 * FIPS 180-2 (appendix B: "abc", the 448-bit message, one million 'a'), in memory and
 * through files, the file of a million bytes read in several chunks; and a file that
 * cannot be read. The batch metadata against Python's hashlib: tests/cli/batch.sh. */
#define _POSIX_C_SOURCE 200809L /* mkstemp */
#include "support/test_util.h"

#include "cli/sha256.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static const char ABC[] = "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad";
static const char MSG448[] = "abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq";
static const char H448[] = "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1";
static const char MILLION_A[] = "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0";
static const char EMPTY[] = "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855";

static void test_in_memory(void **state)
{
    (void)state;
    char hex[65];
    sha256_bytes("abc", 3, hex);
    assert_string_equal(hex, ABC);
    sha256_bytes(MSG448, strlen(MSG448), hex);
    assert_string_equal(hex, H448);
    sha256_bytes("", 0, hex);
    assert_string_equal(hex, EMPTY);
}

/* Writes len bytes to a new temporary file; its path goes to path. */
static void temp_file(char path[64], const void *data, size_t len)
{
    strcpy(path, "/tmp/hp_sha256_XXXXXX");
    int fd = mkstemp(path);
    assert_true(fd >= 0);
    assert_int_equal(write(fd, data, len), (ssize_t)len);
    assert_int_equal(close(fd), 0);
}

static void test_files(void **state)
{
    (void)state;
    char path[64], hex[65];
    temp_file(path, "abc", 3);
    assert_int_equal(sha256_file(path, hex), 0);
    assert_string_equal(hex, ABC);
    unlink(path);

    size_t n = 1000000; /* more than sha256_file's 64 KiB read buffer */
    char *a = malloc(n);
    assert_non_null(a);
    memset(a, 'a', n);
    temp_file(path, a, n);
    free(a);
    assert_int_equal(sha256_file(path, hex), 0);
    assert_string_equal(hex, MILLION_A);
    unlink(path);

    errno = 0;
    assert_int_equal(sha256_file(path, hex), -1); /* removed just above */
    assert_int_equal(errno, ENOENT);
}

int main(void)
{
    const struct CMUnitTest tests[] = {cmocka_unit_test(test_in_memory),
                                       cmocka_unit_test(test_files)};
    return cmocka_run_group_tests(tests, NULL, NULL);
}
