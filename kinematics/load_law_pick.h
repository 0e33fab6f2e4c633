/* A load model's contact law, chosen after creation. Internal (not installed).
 *
 * hp_load_model_create gives a model the law its spec names (hp_load_spec.law). The
 * fidelity benchmark (bench/bench_fidelity.c) needs the same layout and load under the law
 * fitted to the finite-element reference, whatever law the load level plans with, to find
 * where the head really rests under a plan's pressures; and it must know which law the
 * load level used, to say what the load level's row measures. */
#ifndef HP_LOAD_LAW_PICK_H
#define HP_LOAD_LAW_PICK_H

#include "kinematics/contact_law.h"
#include "headplan/hp_load.h"

/* The law M evaluates (HP_CLAW_LAW_CAP for NULL M). */
hp_claw_law hpi_load_model_law(const hp_load_model *M);

/* Makes M evaluate law from now on (every other field of M is law-independent).
 * HP_ERR_NULL for NULL M, HP_ERR_INVALID for a law that does not exist; M unchanged then. */
hp_error hpi_load_model_set_law(hp_load_model *M, hp_claw_law law);

/* The first carrying bladder (P_k > 0, in contact) whose contact state at pose xi with
 * pressures P lies outside the fitted law's domain (hpi_claw_fem_domain), whatever law M
 * evaluates: *bladder gets its index and *group the group it leaves; -1 and HP_CLAW_IN when
 * every carrying bladder is inside. HP_OK, or hp_load_indentation's error. */
hp_error hpi_load_fem_domain_at(const hp_load_model *M, const double xi[6], const double *P,
                                int *bladder, hp_claw_domain *group);

#endif
