/* The bladder module's name tables and the name/parse calls made from them. */
#include "headplan/hp_iab.h"
#include "common/names.h"
#include "iab/names.h"

const char *const hpi_material_convention_words[] = {"paper", "fe", NULL};

HP_NAMES_CALLS(hp_material_convention, hpi_material_convention_words, hp_material_convention_name,
               hp_material_convention_parse)
