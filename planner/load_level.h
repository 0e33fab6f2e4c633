/* Internal: the load level of hp_planner (load_level.c). The planner owns one of these when
 * its level is HP_LEVEL_LOAD and hands hp_plan and the previous-answer calls to it; the
 * solves it runs are the backend's load_hold (problem.h) and the load solves of
 * load_solve.h. */
#ifndef HP_PLANNER_LOAD_LEVEL_H
#define HP_PLANNER_LOAD_LEVEL_H

#include "kinematics/load_internal.h"
#include "planner/load_solve.h"
#include "planner/problem.h"

typedef struct hp_load_level {
    hp_load_model M;    /* embedded: hp_planner_create stays the only allocation */
    hp_identifiable id; /* the range of corrections hp_plan accepts, accepted here too */
    hp_settings set;
    const hp_backend_ops *ops; /* the configured backend: its load_hold tie-breaks HOLD */
    double lo[HP_MAX_BLADDERS], hi[HP_MAX_BLADDERS];
    unsigned lo_bind[HP_MAX_BLADDERS], hi_bind[HP_MAX_BLADDERS];
    /* The inner radii [m] of the stretch limits and of the cap (limit point, stress):
     * a returned ri is kept inside them to the last bit. */
    double ri_lo[HP_MAX_BLADDERS], ri_hi[HP_MAX_BLADDERS];
    /* This plan's bounds: the above cut by the rate limits around prev_P (plan_bounds). */
    double elo[HP_MAX_BLADDERS], ehi[HP_MAX_BLADDERS];
    unsigned elo_bind[HP_MAX_BLADDERS], ehi_bind[HP_MAX_BLADDERS];
    double start_P[HP_MAX_BLADDERS]; /* the previous pressures after create and reset */
    double prev_P[HP_MAX_BLADDERS];
    double prev_xi[6];
    int have_prev; /* prev_P came from a plan or a set_previous call: rate limits apply */
    /* The last returned pressures and pose (an answer or the safe output), which
     * hp_planner_load_info describes. */
    double last_P[HP_MAX_BLADDERS];
    double last_xi[6];
    /* The last plan's answer was found instead of a saddle (stable_answer, flagged
     * HP_BIND_STABILITY): its distance [mm/deg] from the desired pose and from the saddle's
     * pose, for the note (hpi_load_level_note). */
    int stab_found, stab_was_reached;
    double stab_from_desired, stab_from_saddle;
    char *err; /* the planner's error text (HP_DIAG_MAX bytes) */
} hp_load_level;

/* The load model of layout L at settings s (load, load_geometry) into p (zeroed by the
 * caller): what auto needs to decide (hp_load_auto_choose). */
hp_error hpi_load_level_model(hp_load_level *p, const hp_layout *L, const hp_settings *s,
                              hp_diag *diag);
/* The rest of the load level on a model from hpi_load_level_model: a head that is not a
 * sphere, the backend's load capability, the bounds, the layout's ability to carry the load; err is where the
 * messages of plans go. */
hp_error hpi_load_level_build(hp_load_level *p, const hp_settings *s, const hp_backend_ops *ops,
                              char *err, hp_diag *diag);
/* hp_plan at the load level (hp_planner.h). */
hp_error hpi_load_level_plan(hp_load_level *p, const double desired[6], hp_result *r);
/* hp_planner_load_info of the last returned pressures and pose. */
hp_error hpi_load_level_info(const hp_load_level *p, hp_load_info *info);
/* What a CLOSEST answer's note adds at the load level, appended to buf (HP_DIAG_MAX
 * bytes): for an answer found instead of a saddle, what it is and how far; else nothing.
 * Formats without printf (hp_planner_note's rule). */
void hpi_load_level_note(const hp_load_level *p, char *buf);
/* The static pressure bounds (n values each). */
void hpi_load_level_bounds(const hp_load_level *p, double *lo, double *hi);
/* The previous-answer calls of hp_planner.h at the load level: pressures inside the static
 * bounds (else HP_ERR_INVALID, message in err, nothing changes). */
hp_error hpi_load_level_set_previous(hp_load_level *p, const double *pressures);
hp_error hpi_load_level_set_previous_result(hp_load_level *p, const hp_result *r);
/* The state after create: start_P at the nominal pose, no previous plan. */
void hpi_load_level_reset(hp_load_level *p);

#endif
