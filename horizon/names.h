/* The horizon module's name table (common/names.h): the predictions, in enum order. */
#ifndef HP_HORIZON_NAMES_H
#define HP_HORIZON_NAMES_H

extern const char *const hpi_prediction_words[];

#endif
