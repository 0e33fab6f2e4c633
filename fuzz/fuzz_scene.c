/* libFuzzer target: the scene-file parsers (YAML) on arbitrary bytes: the kind probe and
 * both readers (each also runs the other on a file of the other kind). */
#include "headplan/hp_scene.h"

#include <stddef.h>
#include <stdint.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    hp_scene sc; /* 4.8 KB and 2.3 KB: small enough for the fuzzer's stack */
    hp_bladder_study st;
    hp_diag d;
    (void)hp_scene_kind_of((const char *)data, size);
    (void)hp_scene_parse((const char *)data, size, "fuzz.yaml", &sc, &d);
    (void)hp_study_parse((const char *)data, size, "fuzz.yaml", &st, &d);
    return 0;
}
