/* One check per planner-settings field, shared by hp_settings_validate and by the scene
 * reader (which reports the failing key with file:line:col). A check takes the value in SI
 * (as hp_settings holds it) and returns NULL when it is acceptable, else the reason as a
 * phrase ("must be finite and > 0"), so both callers say the same thing. */
#ifndef HP_SETTINGS_CHECK_H
#define HP_SETTINGS_CHECK_H

/* The weight W (mm per degree) enters the objective squared and inverted; outside this
 * range 1/W² overflows or underflows to 0 and the closest answer loses a whole axis. */
#define HP_WEIGHT_MM_PER_DEG_MIN 1e-6
#define HP_WEIGHT_MM_PER_DEG_MAX 1e6
/* Largest pose tolerance (mm and degrees). The tolerance decides REACHED: beyond a
 * millimetre (twice the clinical 0.5) an answer that far from its correction would be called
 * reached (with 1e300, one 17.7 mm short). */
#define HP_TOLERANCE_MAX 1.0
/* Longest iteration budget and time budget a plan may be given. */
#define HP_MAX_ITER_MAX 1000000
#define HP_MAX_TIME_MAX 3600.0
/* Most restarts a plan may be given: each is a full solve. */
#define HP_RESTARTS_MAX 64

/* How a message names settings.auto_pose: the field, and what it is to a caller who gave a
 * correction (the command line sets it to the correction planned). */
#define HPI_AUTO_POSE_NAME "auto_pose (the correction auto measures at)"

const char *hpi_check_level_tolerance(double v); /* [m] */
const char *hpi_check_auto_trans(double v);      /* [m] */
const char *hpi_check_auto_rot(double v);        /* [rad] */
const char *hpi_check_tolerance(double v);       /* mm and degrees */
const char *hpi_check_max_iter(long v);
const char *hpi_check_max_time(double v); /* [s] */
const char *hpi_check_weight(double v);   /* mm per degree */
const char *hpi_check_restarts(long v);

#endif
