/* Internal: the request check every planner applies to a desired correction (hp_plan and
 * hp_load_plan), so both levels accept and refuse exactly the same corrections with the
 * same words. Allocation-free (messages via plan_text.c). */
#ifndef HP_PLANNER_PLAN_RANGE_H
#define HP_PLANNER_PLAN_RANGE_H

#include "common/units.h"
#include "headplan/hp_contact.h"

/* Largest correction hp_plan accepts: far beyond any bladder's reach, small enough that
 * every contact model stays well defined. */
#define HP_PLAN_MAX_TRANS 1.0 /* [m] */
#define HP_PLAN_MAX_ROT HP_PI /* [rad] */
/* What a component beyond them is told. */
#define HP_PLAN_RANGE_TEXT "out of range (|translation| <= 1 m, |rotation| <= pi rad)"

/* A pose's components in hp_plan's order: "x", "y", "z", "pitch", "roll", "yaw". */
extern const char *const hpi_pose_component_names[6];

/* The first component of pose xi (SI) that is not finite or lies beyond HP_PLAN_MAX_TRANS
 * (translation) or HP_PLAN_MAX_ROT (rotation), else -1: the check hp_plan applies to a
 * desired correction and hp_settings_validate to auto_pose. */
int hpi_plan_pose_out_of_range(const double xi[6]);

/* Where pose xi (SI) lies against the layout's identifiable range id (hp_identifiable): 0
 * inside; 1 its translation norm is beyond trans_limit; 2 its rotation angle is not below
 * rot_limit (never for a layout that sees only the centre). *size (may be NULL) gets that
 * norm [m] or angle [rad]. The one test the plans, the reach and the previous answer share. */
int hpi_plan_range_check(const hp_identifiable *id, const double xi[6], double *size);

/* 1 when pose xi (SI) lies in the identifiable range id; else 0 with "WHAT translation: ..."
 * or "WHAT rotation: ..." in err (HP_DIAG_MAX bytes), the size and the limit named. */
int hpi_plan_range_ok(const hp_identifiable *id, const double xi[6], const char *what, char *err);

/* The request: desired finite, each translation within HP_PLAN_MAX_TRANS and rotation
 * within HP_PLAN_MAX_ROT, and inside the identifiable range id. 1 when it passes, else 0
 * with the one-line reason (the component or the limit named) in err (HP_DIAG_MAX bytes). */
int hpi_plan_desired_ok(const hp_identifiable *id, const double desired[6], char *err);

#endif
