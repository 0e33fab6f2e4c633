/* The planner's name tables (common/names.h), each in enum order (bindings: bit order). */
#ifndef HP_PLANNER_NAMES_H
#define HP_PLANNER_NAMES_H

extern const char *const hpi_backend_words[];
extern const char *const hpi_status_words[];
extern const char *const hpi_binding_words[];
extern const char *const hpi_load_tiebreak_words[];

#endif
