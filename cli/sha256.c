/* SHA-256 (see sha256.h) by Nettle; tests/cli/test_sha256.c checks the FIPS 180-2 known
 * answers, tests/cli/batch.sh the batch metadata against Python's hashlib. */
#include "cli/sha256.h"

#include <nettle/sha2.h>
#include <stdint.h>
#include <stdio.h>

/* Finishes ctx and writes its digest as hex. */
static void finish(struct sha256_ctx *ctx, char hex[65])
{
    static const char H[] = "0123456789abcdef";
    uint8_t d[SHA256_DIGEST_SIZE];
    sha256_digest(ctx, sizeof d, d);
    for (int i = 0; i < SHA256_DIGEST_SIZE; ++i) {
        hex[2 * i] = H[d[i] >> 4];
        hex[2 * i + 1] = H[d[i] & 15u];
    }
    hex[64] = '\0';
}

void sha256_bytes(const void *data, size_t len, char hex[65])
{
    struct sha256_ctx ctx;
    sha256_init(&ctx);
    sha256_update(&ctx, len, data);
    finish(&ctx, hex);
}

int sha256_file(const char *path, char hex[65])
{
    FILE *f = fopen(path, "rb");
    if (!f) return -1;
    struct sha256_ctx ctx;
    sha256_init(&ctx);
    unsigned char buf[65536];
    size_t n;
    while ((n = fread(buf, 1, sizeof buf, f)) > 0) sha256_update(&ctx, n, buf);
    int bad = ferror(f);
    fclose(f);
    if (bad) return -1;
    finish(&ctx, hex);
    return 0;
}
