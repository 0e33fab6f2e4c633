/* A plan's pressures against the finite-element reference: the one home of the measurement
 * that `headplan solve` prints for its answer, `headplan analyze` for its scene and the
 * benchmark lab's fidelity family
 * (bench/bench_fidelity.c) makes on the catalogue (docs/accuracy.md §5.7).
 *
 * The pressures are held and the head let go under its weight: its rest (hp_load_rest,
 * surface geometry) on a load model that evaluates the contact law fitted to the CalculiX
 * tables, from the pose the plan claims. The error is that rest against the claimed pose.
 * With a band b > 0, the law's own error is bounded too: the rests with the force scaled by
 * 1 + b and 1 − b (a force scaled by s rests where the weight over s does, so the model's
 * mass is divided by s), the larger deviation reported. */
#ifndef CLI_FIDELITY_H
#define CLI_FIDELITY_H

#include "headplan/headplan.h"

#include <stddef.h>

/* What the bladders carry in a fidelity measurement: the scene's load when it states one
 * (returns 1), else the default head's (returns 0): the head's mass, or HP_HEAD_DEFAULT_MASS
 * when the head states none, at its centre under supine gravity (hp_load_spec_default). */
int cli_fidelity_spec(const hp_scene *sc, hp_load_spec *spec);

/* The reference models of a layout and load: the fitted law, and with band > 0 the two
 * scaled ones. */
typedef struct cli_fidelity_ref {
    hp_load_model *M[3];
    int n; /* 1, or 3 with a band */
} cli_fidelity_ref;

/* Builds the models (band in [0, 0.5)). HP_OK, or the first error of hp_load_model_create
 * (the models built so far are freed by cli_fidelity_close, which is always called). */
hp_error cli_fidelity_open(const hp_layout *L, const hp_load_spec *spec, double band,
                           cli_fidelity_ref *r);
void cli_fidelity_close(cli_fidelity_ref *r);

/* One plan's pressures against the reference. */
typedef struct cli_fidelity_result {
    double pose_mm, pose_deg; /* the rest against the claimed pose: translation norm, rotation
                                 angle; +inf: no rest */
    double band_mm, band_deg; /* the larger deviation with the band (= pose_* without one) */
    double indent_max;        /* the largest delta/ro at the rest (NaN: no rest) */
    double carried;           /* share of the weight the bladders bear along gravity at the
                                 claimed pose (1 at a pose the pressures hold) */
    char domain[48];          /* "in", "BLADDER:GROUP" outside the fitted law's domain, or
                                 "no rest" */
} cli_fidelity_result;

void cli_fidelity_measure(const cli_fidelity_ref *r, const double *P, const double xi[6],
                          cli_fidelity_result *out);

/* 1 when a plan of this status is an answer whose pressures are measured (reached, closest,
 * uncommanded: the answers solve prints); 0 for the others (failed, a time or iteration
 * limit, refused input), whose pressures are only the safe output, no plan to measure. */
int cli_fidelity_answered(hp_status status);

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
    cli_fidelity_result m;  /* the measurement, with the band CLI_FIDELITY_LAW_BAND */
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
 * is no answer (cli_fidelity_answered). */
void cli_fidelity_text(const hp_scene *sc, hp_level level, char *buf, size_t len);

/* Translation between two poses [mm]: the norm of the difference of (x, y, z). */
double cli_fidelity_translation_mm(const double a[6], const double b[6]);

#endif
