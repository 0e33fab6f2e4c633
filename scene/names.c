/* The scene module's name tables and the name/parse calls made from them. */
#include "headplan/hp_scene.h"
#include "headplan/hp_trace.h"
#include "common/names.h"
#include "scene/names.h"

const char *const hpi_trace_rows_words[] = {"deviation", "correction", NULL};
const char *const hpi_trace_format_words[] = {"csv", "jsonl", NULL};
const char *const hpi_trace_form_words[] = {"angles", "quaternion", "matrix", NULL};
const char *const hpi_scene_kind_words[] = {"layout", "bladder", NULL};

HP_NAMES_CALLS(hp_trace_rows, hpi_trace_rows_words, hp_trace_rows_name, hp_trace_rows_parse)

HP_NAMES_CALLS(hp_trace_format, hpi_trace_format_words, hp_trace_format_name, hp_trace_format_parse)

HP_NAMES_NAME_CALL(hp_trace_form, hpi_trace_form_words, hp_trace_form_name)

HP_NAMES_NAME_CALL(hp_scene_kind, hpi_scene_kind_words, hp_scene_kind_name)
