/* Scene files: the top level, the model/solver/correction/trace sections, and loading, for
 * both kinds: layout scenes (hp_scene) and single-bladder studies (hp_bladder_study). */
#include "headplan/hp_trace.h"
#include "common/units.h"
#include "planner/settings_check.h"
#include "scene/scene_parts.h"
#include "planner/names.h"
#include "scene/names.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char *const LAYOUT_KEYS[] = {"headplan_scene",   "name",     "head",  "pivot_mm",
                                          "bladder_defaults", "bladders", "model", "solver",
                                          "correction",       "trace",    "load",  NULL};
static const char *const BLADDER_KEYS[] = {"headplan_scene", "name", "bladder", "paper_printed",
                                           NULL};

/* `headplan_scene: 1` must be the first key, so a reader knows the format before anything
 * else is interpreted. */
static hp_error version(const sr_ctx *c, const yt_node *root, int *out)
{
    if (root->type != YT_MAPPING)
        return sr_fail(c, root, "scene", HP_ERR_PARSE,
                       "expected a mapping of keys starting with 'headplan_scene: 1', found %s",
                       sr_type_name(root));
    if (yt_map_size(root) == 0 || strcmp(yt_map_key(root, 0)->value, "headplan_scene") != 0) {
        const yt_node *at = yt_map_size(root) ? yt_map_key(root, 0) : root;
        return sr_fail(c, at, "headplan_scene", HP_ERR_PARSE,
                       "a scene must start with 'headplan_scene: %d'", HP_SCENE_VERSION);
    }
    const yt_node *v = yt_map_value(root, 0);
    long ver;
    hp_error e = sr_integer(c, v, "headplan_scene", 0, 1000000, &ver);
    if (e) return e;
    if (ver != HP_SCENE_VERSION)
        return sr_fail(c, v, "headplan_scene", HP_ERR_PARSE,
                       "unsupported version %ld (this build reads version %d)", ver,
                       HP_SCENE_VERSION);
    *out = (int)ver;
    return HP_OK;
}

static hp_error model(const sr_ctx *c, const yt_node *node, hp_scene *s)
{
    static const char *const KEYS[] = {"level", "tolerance_mm", "auto_translation_mm",
                                       "auto_rotation_deg", NULL};
    hp_error e = sr_map(c, node, "model", KEYS, NULL);
    if (e) return e;
    const yt_node *n;
    if ((n = yt_map_get(node, "level"))) {
        const char *LEVELS[HP_LEVEL_LOAD + 2]; /* every level, "load" last, NULL */
        for (int l = HP_LEVEL_LINEAR; l <= HP_LEVEL_LOAD; ++l)
            LEVELS[l] = hp_level_name((hp_level)l);
        LEVELS[HP_LEVEL_LOAD + 1] = NULL;
        char name[16];
        if ((e = sr_word(c, n, "model.level", "level", LEVELS, name, sizeof name))) return e;
        /* "load" is the load level (docs/load.md; hp_scene_settings gives HP_LEVEL_LOAD);
         * its contact geometry is `load.geometry`, and s->level keeps the surface level
         * for a caller that analyses the scene's contact geometry. */
        s->level_load = strcmp(name, HP_SCENE_LEVEL_LOAD) == 0;
        if (s->level_load && !s->has_load)
            return sr_fail(c, n, "model.level", HP_ERR_INVALID,
                           "'load' needs a 'load' section (what the bladders carry)");
        if (s->level_load) s->level = HP_LEVEL_SURFACE;
        else (void)hp_level_parse(name, &s->level); /* cannot fail: name is in LEVELS */
    }
    if ((n = yt_map_get(node, "tolerance_mm"))) {
        double t;
        const char *why;
        if ((e = sr_number(c, n, "model.tolerance_mm", &t))) return e;
        if ((why = hpi_check_level_tolerance(t * 1e-3)))
            return sr_fail(c, n, "model.tolerance_mm", HP_ERR_INVALID, "%s mm (got %g)", why, t);
        s->level_tolerance = t * 1e-3;
    }
    const yt_node *tr = yt_map_get(node, "auto_translation_mm");
    const yt_node *ro = yt_map_get(node, "auto_rotation_deg");
    if (!tr != !ro)
        return sr_fail(c, node, tr ? "model.auto_rotation_deg" : "model.auto_translation_mm",
                       HP_ERR_PARSE,
                       "missing required key (auto_translation_mm and auto_rotation_deg go "
                       "together)");
    if (tr) {
        double a, b;
        const char *why;
        if ((e = sr_number(c, tr, "model.auto_translation_mm", &a))) return e;
        if ((why = hpi_check_auto_trans(a * 1e-3)))
            return sr_fail(c, tr, "model.auto_translation_mm", HP_ERR_INVALID, "%s mm (got %g)",
                           why, a);
        if ((e = sr_number(c, ro, "model.auto_rotation_deg", &b))) return e;
        if (!(b >= 0 && b <= 180))
            return sr_fail(c, ro, "model.auto_rotation_deg", HP_ERR_INVALID,
                           "must be in [0, 180] deg (got %g)", b);
        s->has_auto_range = 1;
        s->auto_trans = a * 1e-3;
        s->auto_rot = b * HP_RAD_PER_DEG;
    }
    return HP_OK;
}

static hp_error solver(const sr_ctx *c, const yt_node *node, hp_scene *s)
{
    static const char *const KEYS[] = {"backend",           "tolerance", "max_iter", "max_time_s",
                                       "weight_mm_per_deg", "restarts",  NULL};
    hp_error e = sr_map(c, node, "solver", KEYS, NULL);
    if (e) return e;
    const yt_node *n;
    if ((n = yt_map_get(node, "backend"))) {
        char name[16];
        if ((e = sr_word(c, n, "solver.backend", "backend", hpi_backend_words, name, sizeof name)))
            return e;
        (void)hp_backend_parse(name, &s->backend); /* cannot fail: name is in the table */
    }
    /* The planner's own per-field checks (planner/settings_check.h), so a value the
     * planner would refuse is refused here, at its line and column. */
    static const char *const POS[3] = {"tolerance", "max_time_s", "weight_mm_per_deg"};
    const char *(*const check[3])(double) = {hpi_check_tolerance, hpi_check_max_time,
                                             hpi_check_weight};
    double *dst[3] = {&s->tolerance, &s->max_time, &s->weight_mm_per_deg};
    for (int i = 0; i < 3; ++i) {
        if (!(n = yt_map_get(node, POS[i]))) continue;
        char p[SR_PATH_MAX];
        double v;
        const char *why;
        sr_join(p, sizeof p, "solver", POS[i]);
        if ((e = sr_number(c, n, p, &v))) return e;
        if ((why = check[i](v))) return sr_fail(c, n, p, HP_ERR_INVALID, "%s (got %g)", why, v);
        *dst[i] = v;
    }
    if ((n = yt_map_get(node, "max_iter"))) {
        long it;
        if ((e = sr_integer(c, n, "solver.max_iter", 1, HP_MAX_ITER_MAX, &it))) return e;
        s->max_iter = (int)it;
    }
    if ((n = yt_map_get(node, "restarts"))) {
        long r;
        if ((e = sr_integer(c, n, "solver.restarts", 0, HP_RESTARTS_MAX, &r))) return e;
        s->restarts = (int)r;
    }
    return HP_OK;
}

static hp_error correction(const sr_ctx *c, const yt_node *node, hp_scene *s)
{
    static const char *const KEYS[] = {"x_mm",     "y_mm",    "z_mm", "pitch_deg",
                                       "roll_deg", "yaw_deg", NULL};
    hp_error e = sr_map(c, node, "correction", KEYS, NULL);
    if (e) return e;
    double v[6];
    for (int i = 0; i < 6; ++i) {
        const yt_node *n;
        char p[SR_PATH_MAX];
        if ((e = sr_require(c, node, "correction", KEYS[i], &n))) return e;
        sr_join(p, sizeof p, "correction", KEYS[i]);
        if ((e = sr_number(c, n, p, &v[i]))) return e;
    }
    hp_pose_from_clinical(v, s->correction);
    s->has_correction = 1;
    return HP_OK;
}

/* The trace path as given, or joined to the scene file's folder when relative. */
static hp_error trace(const sr_ctx *c, const yt_node *node, hp_scene *s)
{
    static const char *const KEYS[] = {"file", "rows", NULL};
    hp_error e = sr_map(c, node, "trace", KEYS, NULL);
    if (e) return e;
    const yt_node *f, *r;
    char file[HP_SCENE_PATH_MAX], rows[16];
    if ((e = sr_require(c, node, "trace", "file", &f))) return e;
    if ((e = sr_text(c, f, "trace.file", file, sizeof file))) return e;
    if ((e = sr_require(c, node, "trace", "rows", &r))) return e;
    if ((e = sr_word(c, r, "trace.rows", "rows", hpi_trace_rows_words, rows, sizeof rows)))
        return e;
    (void)hp_trace_rows_parse(rows, &s->trace_rows); /* cannot fail: rows is in the table */
    const char *slash = strrchr(c->file, '/');
    int n;
    if (file[0] == '/' || !slash) n = snprintf(s->trace_path, sizeof s->trace_path, "%s", file);
    else
        n = snprintf(s->trace_path, sizeof s->trace_path, "%.*s/%s", (int)(slash - c->file),
                     c->file, file);
    if (n < 0 || (size_t)n >= sizeof s->trace_path)
        return sr_fail(c, f, "trace.file", HP_ERR_INVALID, "path longer than %d characters",
                       HP_SCENE_PATH_MAX - 1);
    s->has_trace = 1;
    return HP_OK;
}

static hp_error layout_scene(const sr_ctx *c, const yt_node *root, hp_scene *s)
{
    hp_error e = sr_map(c, root, "", LAYOUT_KEYS, NULL);
    if (e) return e;
    const yt_node *n, *list;
    if ((e = sr_require(c, root, "", "head", &n))) return e;
    if ((e = sp_head(c, n, "head", &s->layout.head))) return e;
    if ((n = yt_map_get(root, "pivot_mm"))) {
        double p[3];
        if ((e = sr_vector(c, n, "pivot_mm", 3, p))) return e;
        for (int i = 0; i < 3; ++i) s->layout.pivot[i] = p[i] * 1e-3;
    }
    const yt_node *defaults = yt_map_get(root, "bladder_defaults");
    if (defaults) {
        static const char *const KEYS[] = {
            "Ri_mm",       "Ro_mm",       "material",     "pressure_min_kpa", "pressure_max_kpa",
            "stretch_min", "stretch_max", "rate_max_kpa", "stress_max_kpa",   NULL};
        hp_bladder scratch;
        if ((e = sr_map(c, defaults, "bladder_defaults", KEYS, NULL))) return e;
        if ((e = sp_bladder_params(c, defaults, "bladder_defaults", NULL, 0, &scratch))) return e;
    }
    if ((e = sr_require(c, root, "", "bladders", &list))) return e;
    if ((e = sp_bladders(c, list, defaults, &s->layout))) return e;
    hp_diag sub;
    sub.text[0] = '\0';
    if ((e = hp_layout_prepare(&s->layout, &sub)))
        return sr_fail(c, list, "bladders", e, "%s", sub.text);
    if ((n = yt_map_get(root, "load")) && (e = sp_load(c, n, s))) return e;
    if ((n = yt_map_get(root, "model")) && (e = model(c, n, s))) return e;
    if ((n = yt_map_get(root, "solver")) && (e = solver(c, n, s))) return e;
    if ((n = yt_map_get(root, "correction")) && (e = correction(c, n, s))) return e;
    if ((n = yt_map_get(root, "trace")) && (e = trace(c, n, s))) return e;
    return HP_OK;
}

static hp_error bladder_scene(const sr_ctx *c, const yt_node *root, hp_bladder_study *s)
{
    hp_error e = sr_map(c, root, "", BLADDER_KEYS, "in a single-bladder scene");
    if (e) return e;
    if ((e = sp_study(c, yt_map_get(root, "bladder"), s))) return e;
    const yt_node *n = yt_map_get(root, "paper_printed");
    if (n && (e = sp_printed(c, n, s))) return e;
    return HP_OK;
}

/* The first keys of either kind: `headplan_scene` and `name`. */
static hp_error head_keys(const sr_ctx *c, const yt_node *root, int *ver, char *name, size_t size)
{
    hp_error e = version(c, root, ver);
    if (e) return e;
    const yt_node *n;
    if ((e = sr_require(c, root, "", "name", &n))) return e;
    return sr_text(c, n, "name", name, size);
}

static hp_error study_tree(const sr_ctx *c, const yt_node *root, hp_bladder_study *s);
static hp_error layout_tree_v(const sr_ctx *c, const yt_node *root, void *out);
static hp_error study_tree_v(const sr_ctx *c, const yt_node *root, void *out);

/* A file of the other kind: judged by that kind's reader (into a scratch struct of size
 * bytes), so it gets that reader's message when malformed; else refused as `what`. */
static hp_error wrong_kind(const sr_ctx *c, const yt_node *root, size_t size,
                           hp_error (*tree)(const sr_ctx *, const yt_node *, void *),
                           const char *what)
{
    void *t = calloc(1, size);
    if (!t) return hp_diag_set(c->diag, HP_ERR_NOMEM, "%s: out of memory", c->file);
    hp_error e = tree(c, root, t);
    free(t);
    if (e) return e;
    return hp_diag_set(c->diag, HP_ERR_INVALID, "%s: %s", c->file, what);
}

/* A layout scene. A single-bladder study given to this reader is judged by the study
 * reader first (so a file gets the same message whichever reader it is given to), then
 * refused as the wrong kind. */
static hp_error layout_tree(const sr_ctx *c, const yt_node *root, hp_scene *s)
{
    hp_error e = head_keys(c, root, &s->version, s->name, sizeof s->name);
    if (e) return e;
    if (yt_map_get(root, "bladder"))
        return wrong_kind(c, root, sizeof(hp_bladder_study), study_tree_v,
                          "a single-bladder study, not a layout scene (read it with "
                          "hp_study_load)");
    /* One set of defaults: the planner's, except the level: a scene that states none is
     * planned at the fidelity it needs (auto), not silently at the cheapest level. */
    hp_settings def;
    hp_settings_default(&def);
    s->level = HP_SCENE_DEFAULT_LEVEL;
    s->level_tolerance = def.level_tolerance;
    s->auto_trans = def.auto_trans;
    s->auto_rot = def.auto_rot;
    s->backend = def.backend;
    s->tolerance = def.tolerance;
    s->max_iter = def.max_iter;
    s->max_time = def.max_time;
    s->weight_mm_per_deg = def.weight_mm_per_deg;
    s->restarts = def.restarts;
    if (!yt_map_get(root, "bladders"))
        return sr_fail(c, root, "bladders", HP_ERR_PARSE,
                       "missing required key (a scene has 'bladders' and a 'head', or one "
                       "'bladder' study)");
    return layout_scene(c, root, s);
}

/* A single-bladder study; a layout scene is judged by the layout reader, then refused. */
static hp_error study_tree(const sr_ctx *c, const yt_node *root, hp_bladder_study *s)
{
    hp_error e = head_keys(c, root, &s->version, s->name, sizeof s->name);
    if (e) return e;
    if (!yt_map_get(root, "bladder"))
        return wrong_kind(c, root, sizeof(hp_scene), layout_tree_v,
                          "a layout scene, not a single-bladder study (read it with "
                          "hp_scene_load)");
    return bladder_scene(c, root, s);
}

/* One kind's reader: its output struct, where its file name goes, and its tree reader. */
typedef struct kind_reader {
    void *out;
    size_t size;
    char *file; /* inside out, HP_SCENE_PATH_MAX bytes */
    hp_error (*tree)(const sr_ctx *c, const yt_node *root, void *out);
} kind_reader;

static hp_error layout_tree_v(const sr_ctx *c, const yt_node *root, void *out)
{
    return layout_tree(c, root, out);
}

static hp_error study_tree_v(const sr_ctx *c, const yt_node *root, void *out)
{
    return study_tree(c, root, out);
}

/* Parses text into r->out, which is all zero unless the whole file is valid. */
static hp_error parse_with(const char *text, size_t len, const char *filename, const kind_reader *r,
                           hp_diag *diag)
{
    memset(r->out, 0, r->size);
    const char *file = filename ? filename : "<scene>";
    if (!text) return hp_diag_set(diag, HP_ERR_NULL, "%s: NULL text", file);
    if (len > HP_SCENE_MAX_BYTES)
        return hp_diag_set(diag, HP_ERR_PARSE, "%s: larger than the 1 MiB limit (%zu bytes)", file,
                           len);
    sr_ctx c = {.file = file, .diag = diag};
    yt_node *root = NULL;
    hp_error e = yt_parse(text, len, file, &root, diag);
    if (e == HP_OK) {
        snprintf(r->file, HP_SCENE_PATH_MAX, "%s", file);
        e = r->tree(&c, root, r->out);
    }
    if (e != HP_OK) memset(r->out, 0, r->size);
    yt_free(root);
    return e;
}

hp_error hp_scene_parse(const char *text, size_t len, const char *filename, hp_scene *out,
                        hp_diag *diag)
{
    if (!out) return hp_diag_set(diag, HP_ERR_NULL, "scene: NULL output");
    kind_reader r = {out, sizeof *out, out->file, layout_tree_v};
    return parse_with(text, len, filename, &r, diag);
}

hp_error hp_study_parse(const char *text, size_t len, const char *filename, hp_bladder_study *out,
                        hp_diag *diag)
{
    if (!out) return hp_diag_set(diag, HP_ERR_NULL, "study: NULL output");
    kind_reader r = {out, sizeof *out, out->file, study_tree_v};
    return parse_with(text, len, filename, &r, diag);
}

/* The file's bytes (at most HP_SCENE_MAX_BYTES) in *buf (malloc'd; the caller frees it). */
static hp_error read_file(const char *path, char **buf, size_t *len, hp_diag *diag)
{
    *buf = NULL;
    FILE *f = fopen(path, "rb");
    if (!f) return hp_diag_set(diag, HP_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
    /* Read at most one byte past the limit: enough to know the file is too large. */
    char *b = malloc(HP_SCENE_MAX_BYTES + 1);
    if (!b) {
        fclose(f);
        return hp_diag_set(diag, HP_ERR_NOMEM, "%s: out of memory", path);
    }
    errno = 0;
    size_t n = fread(b, 1, HP_SCENE_MAX_BYTES + 1, f);
    int failed = ferror(f), why = errno;
    fclose(f);
    hp_error e = HP_OK;
    if (failed)
        e = hp_diag_set(diag, HP_ERR_IO, "%s: cannot read: %s", path,
                        why ? strerror(why) : "read error");
    else if (n > HP_SCENE_MAX_BYTES)
        e = hp_diag_set(diag, HP_ERR_PARSE, "%s: larger than the 1 MiB limit", path);
    if (e != HP_OK) {
        free(b);
        return e;
    }
    *buf = b;
    *len = n;
    return HP_OK;
}

static hp_error load_with(const char *path, const kind_reader *r, hp_diag *diag)
{
    memset(r->out, 0, r->size);
    if (!path) return hp_diag_set(diag, HP_ERR_NULL, "scene: NULL path");
    char *buf;
    size_t len;
    hp_error e = read_file(path, &buf, &len, diag);
    if (e == HP_OK) e = parse_with(buf, len, path, r, diag);
    free(buf);
    return e;
}

hp_error hp_scene_load(const char *path, hp_scene *out, hp_diag *diag)
{
    if (!out) return hp_diag_set(diag, HP_ERR_NULL, "scene: NULL output");
    kind_reader r = {out, sizeof *out, out->file, layout_tree_v};
    return load_with(path, &r, diag);
}

hp_error hp_study_load(const char *path, hp_bladder_study *out, hp_diag *diag)
{
    if (!out) return hp_diag_set(diag, HP_ERR_NULL, "study: NULL output");
    kind_reader r = {out, sizeof *out, out->file, study_tree_v};
    return load_with(path, &r, diag);
}

hp_scene_kind hp_scene_kind_of(const char *text, size_t len)
{
    hp_scene_kind k = HP_SCENE_LAYOUT;
    yt_node *root = NULL;
    if (text && len <= HP_SCENE_MAX_BYTES && yt_parse(text, len, "<scene>", &root, NULL) == HP_OK &&
        root && root->type == YT_MAPPING && yt_map_get(root, "bladder"))
        k = HP_SCENE_BLADDER;
    yt_free(root);
    return k;
}

hp_scene_kind hp_scene_file_kind(const char *path)
{
    char *buf = NULL;
    size_t len = 0;
    hp_scene_kind k = HP_SCENE_LAYOUT;
    if (path && read_file(path, &buf, &len, NULL) == HP_OK) k = hp_scene_kind_of(buf, len);
    free(buf);
    return k;
}
