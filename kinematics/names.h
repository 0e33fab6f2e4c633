/* The kinematics module's name tables (common/names.h), each in enum order. */
#ifndef HP_KINEMATICS_NAMES_H
#define HP_KINEMATICS_NAMES_H

extern const char *const hpi_level_words[]; /* the contact levels, auto last */
extern const char *const hpi_head_shape_words[];

#endif
