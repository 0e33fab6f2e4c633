/* The horizon module's name table and the name/parse calls made from it. */
#include "headplan/hp_horizon.h"
#include "common/names.h"
#include "horizon/names.h"

const char *const hpi_prediction_words[] = {"hold", "velocity", "periodic", NULL};

HP_NAMES_CALLS(hp_prediction, hpi_prediction_words, hp_prediction_name, hp_prediction_parse)
