/* SHA-256 (FIPS 180-4) of a file, for the batch output's metadata: which scene and which
 * trace produced a result, checkable with `sha256sum`. Computed by Nettle (Debian package
 * nettle-dev), which uses the CPU's SHA instructions where it has them: a hand-written
 * version cost about 3,200 instructions per batch row of a generated trace (~50 bytes)
 * through hashing the trace file alone. */
#ifndef CLI_SHA256_H
#define CLI_SHA256_H

#include <stddef.h>

/* Writes the digest of the len bytes at data as 64 lowercase hex digits and a NUL. */
void sha256_bytes(const void *data, size_t len, char hex[65]);

/* Hashes the file at path into hex; returns 0, or -1 (errno set) when it cannot be read. */
int sha256_file(const char *path, char hex[65]);

#endif
