/* The bladder module's name table (common/names.h): the material conventions, in enum order. */
#ifndef HP_IAB_NAMES_H
#define HP_IAB_NAMES_H

extern const char *const hpi_material_convention_words[];

#endif
