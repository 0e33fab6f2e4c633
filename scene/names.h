/* The scene module's name tables (common/names.h), each in enum order. */
#ifndef HP_SCENE_NAMES_H
#define HP_SCENE_NAMES_H

extern const char *const hpi_trace_rows_words[];
extern const char *const hpi_trace_format_words[];
extern const char *const hpi_trace_form_words[];
extern const char *const hpi_scene_kind_words[];

#endif
