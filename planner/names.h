/* The planner's name tables (common/names.h), each in enum order (bindings: bit order). */
#ifndef HP_PLANNER_NAMES_H
#define HP_PLANNER_NAMES_H

extern const char *const hp_backend_words[];
extern const char *const hp_status_words[];
extern const char *const hp_binding_words[];
extern const char *const hp_load_tiebreak_words[];

#endif
