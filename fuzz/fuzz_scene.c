/* libFuzzer target: the scene-file parser (YAML) on arbitrary bytes. */
#include "headplan/hp_scene.h"

#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    /* hp_scene is large; keep it off the fuzzer's stack. */
    hp_scene *sc = malloc(sizeof *sc);
    if (!sc) return 0;
    hp_diag d;
    (void)hp_scene_parse((const char *)data, size, "fuzz.yaml", sc, &d);
    free(sc);
    return 0;
}
