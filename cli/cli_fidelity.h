/* The model error the command line states (`headplan solve`, `headplan analyze`) and the
 * fidelity plans the benchmark lab's fidelity family makes (bench/bench_fidelity.c,
 * docs/accuracy.md §5.7): the measurement itself is planner/model_error.h's. */
#ifndef CLI_FIDELITY_H
#define CLI_FIDELITY_H

#include "headplan/headplan.h"
#include "planner/model_error.h"

#include <stddef.h>

/* What the bladders carry in a fidelity measurement: the scene's load when it states one
 * (returns 1), else the default head's (returns 0): the head's mass, or HP_HEAD_DEFAULT_MASS
 * when the head states none, at its centre under supine gravity (hp_load_spec_default). */
int cli_fidelity_spec(const hp_scene *sc, hp_load_spec *spec);

/* The settings a fidelity plan uses at level, from the scene's (base): no rate limits and
 * no warm start (each plan cold, alone); the kinematic levels leave the weight out, the
 * load level carries spec (surface geometry when the scene states no load). */
void cli_fidelity_settings(const hp_scene *sc, const hp_settings *base, hp_level level,
                           const hp_load_spec *spec, hp_settings *s);

/* The fitted law's band the command line states: its worst relative error in force over
 * the in-domain rows of fem/tables/law_error.csv. headplan-bench reads that table at run time
 * (a refit moves it); the command line is installed without the table, so it carries the
 * value, and tests/cli/fidelity_harness.sh fails when the two differ. */
#define CLI_FIDELITY_LAW_BAND 0.0461

/* An answer's model error, as `headplan solve` and `headplan analyze` state it. */
typedef struct cli_model_error {
    hp_level level;         /* the level the answer was planned at */
    double tolerance;       /* the solver's [mm and deg] */
    double mass;            /* the head's mass the reference carries [kg] */
    int own_mass;           /* 1: the scene's load or head mass; 0: the default head's */
    char not_measured[160]; /* why it was not measured ("" when it was) */
    hpi_fidelity_result m;  /* the measurement, with the band CLI_FIDELITY_LAW_BAND */
} cli_model_error;

/* Answer r of scene sc (planned at level with solver tolerance tol) against the reference:
 * its pressures held and the head let go from the pose it claims, under the scene's load
 * (cli_fidelity_spec), with the law's band (three rests). */
void cli_model_error_of(const hp_scene *sc, const hp_result *r, hp_level level, double tol,
                        cli_model_error *e);

/* The model error line into buf (len bytes, no newline), beside the solver's tolerance, e.g.
 * "level load: 0.1234 mm, 0.01 deg against the fitted law, up to 0.13 mm, 0.011 deg with its
 * ±4.61 % band (rest in its domain); solver tolerance 1e-09 mm and deg", "level surface:
 * unbounded (no rest under the fitted law; the pressures bear 0 % of the weight at the
 * planned pose); ...", or "level surface: not measured: plan iteration-limit". */
void cli_model_error_text(const cli_model_error *e, char *buf, size_t len);

/* The model error line of `headplan analyze` into buf (len bytes, no newline): the scene's
 * correction (none: the nominal pose) planned at level with the fidelity settings, then
 * cli_model_error_of and cli_model_error_text; "not measured: plan STATUS" for a plan that
 * is no answer (hpi_fidelity_answered). */
void cli_fidelity_text(const hp_scene *sc, hp_level level, char *buf, size_t len);

#endif
