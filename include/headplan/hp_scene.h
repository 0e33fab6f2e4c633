/* Scene files: everything one study needs, read from YAML (format: docs/scenes.md).
 *
 * Two kinds of scene file, each with its own type and reader:
 *   layout  — hp_scene (hp_scene_load / hp_scene_parse): a head, its bladders (placement,
 *             radii, material, limits), pivot, contact fidelity, solver settings, and a
 *             desired correction and/or a trace file;
 *   bladder — hp_bladder_study (hp_study_load / hp_study_parse): one bladder and one
 *             inverse (ri -> P) or forward (P -> ri) study, optionally with the values a
 *             paper printed for it (the paper's two tables).
 * hp_scene_file_kind / hp_scene_kind_of tell which reader a file is for. Each reader given
 * the other kind judges the file by the other reader first (so a malformed file gets the
 * same message from both), then refuses it as the wrong kind (HP_ERR_INVALID).
 *
 * Files speak clinical units (every key names its unit: _mm, _deg, _pa, _kpa, _kg, _s);
 * everything in hp_scene and hp_bladder_study is SI (m, rad, Pa, kg, s).
 *
 * Errors are one line: "FILE:LINE:COL: KEY.PATH: message" (1-based line and column).
 * On any error the output scene is all zero: nothing partial is returned as valid.
 *
 * The parser allocates while it runs and frees everything before returning; hp_scene and
 * hp_bladder_study hold no pointers (copy them freely) and are small enough for the stack
 * (4 816 and 2 272 bytes on x86-64, most of it the layout and the text buffers).
 * Reentrant; safe in several threads at once. */
#ifndef HP_SCENE_H
#define HP_SCENE_H

#include <stddef.h>

#include "headplan/hp_common.h"
#include "headplan/hp_iab.h"
#include "headplan/hp_contact.h"
#include "headplan/hp_load.h"
#include "headplan/hp_planner.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The format version this build reads (key `headplan_scene`). */
#define HP_SCENE_VERSION 1
/* Larger files are refused before parsing. */
#define HP_SCENE_MAX_BYTES (1024 * 1024)
/* Longest free text (name, notes) kept, including the NUL; longer text is refused. */
#define HP_SCENE_TEXT_MAX 256
/* Longest path kept (trace file, resolved against the scene's folder), including the NUL. */
#define HP_SCENE_PATH_MAX 1024
/* The optional `model` and `solver` sections default to the planner's own HP_DEFAULT_*
 * values (hp_planner.h), except `model.level`: a scene that states none is planned at `auto`
 * (the cheapest level whose error bound meets model.tolerance_mm over the auto range; with a
 * `load` section, the load level when the sag calls for it), not at hp_settings_default()'s
 * linear level, which a scene would otherwise get without saying so. */
#define HP_SCENE_DEFAULT_LEVEL HP_LEVEL_AUTO

typedef enum hp_scene_kind {
    HP_SCENE_LAYOUT = 0, /* key `bladders`: a head and its bladders (hp_scene) */
    HP_SCENE_BLADDER     /* key `bladder`: one bladder study (hp_bladder_study) */
} hp_scene_kind;

/* What a trace row holds. */
typedef enum hp_trace_rows {
    HP_TRACE_DEVIATION = 0, /* measured head deviation; the desired correction is its exact
                               inverse rigid motion (hp_pose_inverse) */
    HP_TRACE_CORRECTION     /* the desired correction itself */
} hp_trace_rows;

/* The single-bladder study's input. */
typedef enum hp_study_input {
    HP_STUDY_IK = 0, /* inner radius given (`ri_mm`): pressure wanted */
    HP_STUDY_FK      /* pressure given (`pressure_pa`): inner radius wanted */
} hp_study_input;

/* One value as a paper printed it: the number and its literal text (e.g. ".033"), so a
 * report can show it verbatim and know its printed precision. */
typedef struct hp_scene_printed {
    int given;     /* 1 when the file states it */
    double value;  /* in the unit its key names (m, Pa, m³), exactly as printed */
    char text[32]; /* the literal from the file */
} hp_scene_printed;

/* A layout scene (a file whose top level has `bladders` and a `head`). */
typedef struct hp_scene {
    int version;                        /* HP_SCENE_VERSION */
    char name[HP_SCENE_TEXT_MAX];       /* `name` */
    char file[HP_SCENE_PATH_MAX];       /* the file name the scene was read from */
    hp_layout layout;                   /* validated (hp_layout_prepare) */
    hp_level level;                     /* `model.level` (may be HP_LEVEL_AUTO) */
    double level_tolerance;             /* `model.tolerance_mm` [m], > 0 */
    int has_auto_range;                 /* `model.auto_translation_mm` and `_rotation_deg` */
    double auto_trans;                  /* [m] largest translation auto must cover */
    double auto_rot;                    /* [rad] largest rotation auto must cover */
    hp_backend backend;                 /* `solver.backend` */
    double tolerance;                   /* `solver.tolerance` (mm and degrees), > 0 */
    int max_iter;                       /* `solver.max_iter`, 1..1000000 */
    double max_time;                    /* `solver.max_time_s` [s], > 0 */
    double weight_mm_per_deg;           /* `solver.weight_mm_per_deg`, > 0 */
    int restarts;                       /* `solver.restarts`, 0..64 (Ipopt, NLopt SLSQP) */
    int has_correction;                 /* `correction` given */
    double correction[6];               /* [m, m, m, rad, rad, rad]: x y z pitch roll yaw */
    int has_trace;                      /* `trace` given */
    char trace_path[HP_SCENE_PATH_MAX]; /* resolved against the scene file's folder */
    hp_trace_rows trace_rows;

    /* ---- the load level (layout scenes with a `load` section; docs/load.md) ---- */
    int has_load;           /* `load` given */
    double load_fraction;   /* `load.carried_fraction`, in (0, 1] */
    hp_load_spec load;      /* carried mass [kg], centre of mass [m], gravity */
    hp_level load_geometry; /* `load.geometry` (default surface) */
    int load_tiebreak;      /* `load.tiebreak` (an hp_load_tiebreak) */
    int level_load;         /* 1: `model.level: load` asks for the load level */
} hp_scene;

/* A single-bladder study (a file whose top level has `bladder`). */
typedef struct hp_bladder_study {
    int version;                       /* HP_SCENE_VERSION */
    char name[HP_SCENE_TEXT_MAX];      /* `name` */
    char file[HP_SCENE_PATH_MAX];      /* the file name the study was read from */
    hp_iab iab;                        /* radii [m], moduli in the paper's convention [Pa] */
    hp_material_convention convention; /* the convention the file wrote the moduli in */
    double moduli_written[2];          /* the moduli as written (C1,C2 or C10,C01) [Pa] */
    hp_study_input study;
    double study_ri;                       /* [m] input for HP_STUDY_IK, else 0 */
    double study_pressure;                 /* [Pa] input for HP_STUDY_FK, else 0 */
    int has_printed;                       /* `paper_printed` given */
    char printed_title[HP_SCENE_TEXT_MAX]; /* `paper_printed.title` ("" when absent) */
    char printed_note[HP_SCENE_TEXT_MAX];  /* `paper_printed.note` ("" when absent) */
    hp_scene_printed printed_C1;           /* `C1_pa` */
    hp_scene_printed printed_C2;           /* `C2_pa` */
    hp_scene_printed printed_Ri;           /* `Ri_m` */
    hp_scene_printed printed_ri;           /* `ri_m` */
    hp_scene_printed printed_Ro;           /* `Ro_m` */
    hp_scene_printed printed_ro;           /* `ro_m` */
    hp_scene_printed printed_pressure;     /* `pressure_pa` (the paper says Pascals) */
    hp_scene_printed printed_dV;           /* `dV_m3` (the paper prints "≈ 0") */
} hp_bladder_study;

/* Reads and validates the layout scene file at path (at most HP_SCENE_MAX_BYTES). Returns
 * HP_OK, HP_ERR_IO (cannot open or read; diag "FILE: why"), HP_ERR_PARSE (syntax, keys,
 * types, numbers) or HP_ERR_INVALID / HP_ERR_DOMAIN (values out of range, layout is not
 * valid, or a single-bladder study), with the one-line message in diag (may be NULL). out
 * is zeroed on failure. */
HP_API hp_error hp_scene_load(const char *path, hp_scene *out, hp_diag *diag);

/* Parses a scene from memory (len bytes, need not be NUL-terminated). filename is used in
 * messages and to resolve a relative trace path (NULL: "<scene>", relative to the current
 * directory). Same contract as hp_scene_load. */
HP_API hp_error hp_scene_parse(const char *text, size_t len, const char *filename, hp_scene *out,
                               hp_diag *diag);

/* The planner settings a layout scene asks for: hp_settings_default(), then the scene's
 * `model` (level, tolerance, auto range) and `solver` (backend, tolerance, budgets, weight)
 * sections. The one place a scene becomes settings: the command line and the Python module
 * call it too, so a scene plans the same whichever entry point loads it. Returns HP_OK;
 * HP_ERR_NULL for NULL arguments; HP_ERR_INVALID for settings that hp_settings_validate
 * refuses (for an hp_scene filled by hp_scene_load/parse only a load scene's correction
 * beyond 1 m or pi rad, as auto_pose; the message names it). out is filled only on HP_OK.
 *
 * A scene with a `load` section gives its load (load, load_geometry, load_tiebreak) and its
 * correction as auto_pose (where auto measures the levels' model error); one that says
 * `model.level: load` gives HP_LEVEL_LOAD, and one at `auto` lets hp_planner_create choose
 * the load level when the model error at that correction calls for it (hp_planner.h). */
HP_API hp_error hp_scene_settings(const hp_scene *sc, hp_settings *out, hp_diag *diag);

/* The layout analysis of a scene, as `headplan analyze` and the Python analyze() report it.
 * Units SI. */
typedef struct hp_scene_analysis {
    hp_level requested;            /* the settings' level (may be auto) */
    hp_level level;                /* resolved: the level of the analysis and the reach */
    hp_level auto_level;           /* what auto picks for level_tolerance over the range below */
    double trans, rot;             /* [m], [rad] correction size the error bounds cover
                                    (the settings' auto_trans, auto_rot) */
    double bound[HP_LEVEL_COUNT_]; /* [m] each contact geometry's error bound against the
                                         exact distance (hp_contact_error_bound), indexed by
                                         hp_level: 0 for surface, NaN for auto and load */
    hp_identifiable id;            /* what the contact model can tell apart */
    hp_layout_analysis an;         /* at level; an.reach is the planner's (hp_planner_reach) */
} hp_scene_analysis;

/* Analyses layout L under settings s (hp_scene_settings, with any override): the contact
 * models' error bounds and auto's choice (hp_contact_error_bound, hp_contact_auto), the
 * level resolved, hp_layout_identify, hp_layout_analyze at that level, and the reach of a
 * planner at that level (hp_planner_reach). Returns HP_OK, HP_ERR_NULL, or the first step's
 * error with "STEP: reason" in diag (STEP: error bounds, identifiable range, layout
 * analysis, reach). Allocates (a planner, freed before it returns); not real time. */
HP_API hp_error hp_scene_analyze(const hp_layout *L, const hp_settings *s, hp_scene_analysis *out,
                                 hp_diag *diag);

/* Applies one named override to planner settings s, as the command line's options and the
 * Python module's keywords give them: "backend" and "level" (a name: hp_backend_parse,
 * hp_level_parse; the load level is not one of them), "tolerance" (mm and degrees),
 * "max_iter", "max_time_s", "weight_mm_per_deg", "level_tolerance_mm", "warm_start" (0 or
 * 1) and "restarts" (0..64). The value is text (parsed strictly, as a scene's numbers are), or with text NULL the
 * number. Each value is checked by the planner's own check of its field, in the override's
 * units. Returns HP_OK; HP_ERR_NULL; HP_ERR_INVALID (s unchanged) with "NAME: reason" in diag
 * ("level: unknown level 'x' (linear, plane, surface, auto)", "max_time_s: must be > 0 and at
 * most 3600 s (got 0)"), also for a name that is none of these. Allocates nothing. */
HP_API hp_error hp_scene_settings_override(hp_settings *s, const char *name, const char *text,
                                           double number, hp_diag *diag);

/* The name of override i (0-based, in the order above), NULL past the last: the list a
 * front-end offers (the Python module's keywords). */
HP_API const char *hp_scene_override_name(size_t i);

/* What hp_scene_plan_level or hp_scene_kinematic_only refused, so that a caller words (and
 * classes) each refusal in its own terms without reading the message. */
typedef enum hp_level_refusal {
    HP_LEVEL_REFUSED_NONE = 0, /* none refused: HP_OK, HP_ERR_NULL or the load model's error */
    HP_LEVEL_REFUSED_UNKNOWN,  /* the override names no level */
    HP_LEVEL_REFUSED_NO_LOAD,  /* "load" asked of a scene without a `load` section */
    HP_LEVEL_REFUSED_LOAD      /* hp_scene_kinematic_only: the scene is planned at load level */
} hp_level_refusal;

/* Whether scene sc is planned at the load level (docs/load.md), for a caller that draws or
 * analyses the contact levels only (`headplan render`, `analyze`); a planner built from
 * hp_scene_settings decides the same itself (hp_planner_level). level is the
 * caller's override of the scene's model.level ("linear", "plane", "surface", "auto" or
 * "load"; the command line's --level), NULL for the scene's own. *use_load gets 1 when:
 * the level is "load" (the scene's `model.level: load`, or the override); or it is "auto"
 * and the scene has a `load` section and the planner built from the scene's settings
 * resolves auto to the load level (hp_planner_level_for: the one decision, the sag a
 * kinematic plan would leave exceeding model.tolerance_mm). Otherwise 0: a kinematic level
 * plans it. why (may be NULL, len bytes) gets the reason in one line ("load: asked for by
 * model.level", "load: asked for by the caller's level" for the override; for auto the
 * planner's own line, hp_planner_level_choice: "load: predicted sag ... > tolerance ...",
 * or "kinematic: ...; auto chose ..."; "" when the scene has no load and auto was not
 * involved; a caller may word the override's reason in its own terms, as the command line's
 * "--level"). Returns HP_OK; HP_ERR_NULL; HP_ERR_INVALID for an unknown override or
 * "load" on a scene without a `load` section (message in diag; *refused says which); or
 * hp_planner_level_for's error (the layout cannot carry the load model), message in diag.
 * refused (may be NULL) gets HP_LEVEL_REFUSED_NONE unless the level argument itself was
 * refused. Allocates (hp_planner_level_for) only for auto on a scene with a `load` section. */
/* The name of HP_LEVEL_LOAD (hp_level_name), which a scene's model.level and the command
 * line's --level may name besides the contact levels (docs/load.md). */
#define HP_SCENE_LEVEL_LOAD "load"

/* The names of every level, from the one table (hp_level_name; "load" only when
 * with_load), joined by ", " with `last` before the final one (", " or " or "), into buf
 * (len bytes, truncated if short; "linear, plane, surface, auto or load"). Returns buf, for
 * messages and help texts. */
HP_API const char *hp_scene_level_names(int with_load, const char *last, char *buf, size_t len);

HP_API hp_error hp_scene_plan_level(const hp_scene *sc, const char *level, int *use_load, char *why,
                                    size_t len, hp_level_refusal *refused, hp_diag *diag);

/* For a caller that plans the kinematic levels only (`headplan render`): HP_OK when hp_scene_plan_level(sc, level) plans sc kinematically. Else
 * HP_ERR_DOMAIN, *refused = HP_LEVEL_REFUSED_LOAD and diag "FILE: the scene is planned at the
 * load level (WHY), which WHO does not plan: it would plan without the head's weight and
 * disagree with solve" (the caller appends what to do instead); or hp_scene_plan_level's
 * error and refusal (the load model's message prefixed "FILE: load: "). */
HP_API hp_error hp_scene_kinematic_only(const hp_scene *sc, const char *level, const char *who,
                                        hp_level_refusal *refused, hp_diag *diag);

/* Reads and validates the single-bladder study file at path; the same contract as
 * hp_scene_load (a layout scene: its own errors, else HP_ERR_INVALID). */
HP_API hp_error hp_study_load(const char *path, hp_bladder_study *out, hp_diag *diag);
/* The same from memory, as hp_scene_parse. */
HP_API hp_error hp_study_parse(const char *text, size_t len, const char *filename,
                               hp_bladder_study *out, hp_diag *diag);

/* Which reader a scene is for: HP_SCENE_BLADDER when its top level is a mapping with a
 * `bladder` key, else HP_SCENE_LAYOUT (also for text or a file that cannot be read or
 * parsed: the layout reader then says what is wrong). Allocates while it runs. */
HP_API hp_scene_kind hp_scene_kind_of(const char *text, size_t len);
HP_API hp_scene_kind hp_scene_file_kind(const char *path);

/* "layout" / "bladder"; "unknown" otherwise. */
HP_API const char *hp_scene_kind_name(hp_scene_kind k);
/* "deviation" / "correction"; "unknown" otherwise. */
HP_API const char *hp_trace_rows_name(hp_trace_rows r);

#ifdef __cplusplus
}
#endif
#endif
