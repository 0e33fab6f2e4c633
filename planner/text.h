/* Internal: message building without printf (hp_plan must not allocate; printf's float
 * formatting may), into a buffer of HP_DIAG_MAX bytes (text.c). */
#ifndef HP_PLANNER_TEXT_H
#define HP_PLANNER_TEXT_H

#include "headplan/hp_common.h"

void hpi_text_set(char *buf, const char *s);
void hpi_text_add(char *buf, const char *s);
void hpi_text_add_int(char *buf, long long v);
void hpi_text_add_num(char *buf, double v, int dec); /* |v| to dec decimals, with its sign */

#endif
