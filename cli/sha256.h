/* SHA-256 (FIPS 180-4) of a file, for the batch output's metadata: which scene and which
 * trace produced a result, checkable with `sha256sum`. */
#ifndef CLI_SHA256_H
#define CLI_SHA256_H

#include <stddef.h>
#include <stdint.h>

typedef struct sha256 {
    uint32_t h[8];
    uint64_t bytes;
    unsigned char buf[64];
    size_t used;
} sha256;

void sha256_init(sha256 *s);
void sha256_add(sha256 *s, const void *data, size_t len);
/* Finishes and writes 64 lowercase hex digits and a NUL into hex. */
void sha256_hex(sha256 *s, char hex[65]);

/* Hashes the file at path into hex; returns 0, or -1 (errno set) when it cannot be read. */
int sha256_file(const char *path, char hex[65]);

#endif
