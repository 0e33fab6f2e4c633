/* Writing a calibrated layout as a scene file (format: docs/scenes.md), atomically: the text
 * goes to a temporary file in the target's folder, is flushed to disk, then renamed over the
 * target, so a reader sees the old file or the whole new one, never half. */
#define _POSIX_C_SOURCE 200809L
#include "headplan/hp_calib.h"
#include "headplan/hp_planner.h"
#include "common/c_locale.h"
#include "common/units.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* 1 when a and b name the same existing file. */
static int same_file(const char *a, const char *b)
{
    struct stat sa, sb;
    if (stat(a, &sa) != 0 || stat(b, &sb) != 0) return 0;
    return sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
}

static void vec_mm(FILE *f, const double v[3])
{
    fprintf(f, "[%.17g, %.17g, %.17g]", v[0] * 1e3, v[1] * 1e3, v[2] * 1e3);
}

/* Text as a YAML double-quoted scalar (the scene forbids control characters anyway). */
static void quoted(FILE *f, const char *s)
{
    fputc('"', f);
    for (; *s; ++s) {
        if (*s == '"' || *s == '\\') fputc('\\', f);
        if ((unsigned char)*s >= 0x20) fputc(*s, f);
    }
    fputc('"', f);
}

static void write_body(FILE *f, const hp_layout *L, hp_level level, const hp_scene *base,
                       const char *name)
{
    fprintf(f, "headplan_scene: 1\n# Written by headplan fit layout: every bladder by its "
               "calibrated centre.\nname: ");
    quoted(f, name);
    fprintf(f, "\nhead:\n  shape: %s\n", hp_head_shape_name(L->head.shape));
    if (L->head.shape == HP_HEAD_SPHERE)
        fprintf(f, "  radius_mm: %.17g\n", L->head.semi_axes[0] * 1e3);
    else {
        fprintf(f, "  semi_axes_mm: ");
        vec_mm(f, L->head.semi_axes);
        fputc('\n', f);
    }
    fprintf(f, "  center_mm: ");
    vec_mm(f, L->head.center);
    fputc('\n', f);
    if (L->head.mass > 0) fprintf(f, "  mass_kg: %.17g\n", L->head.mass);
    fprintf(f, "pivot_mm: ");
    vec_mm(f, L->pivot);
    fprintf(f, "\nbladders:\n");
    for (int k = 0; k < L->n; ++k) {
        const hp_bladder *b = &L->bladders[k];
        fprintf(f, "  - name: %s\n    center_mm: ", b->name);
        vec_mm(f, b->center);
        fprintf(f, "\n    Ri_mm: %.17g\n    Ro_mm: %.17g\n", b->iab.Ri * 1e3, b->iab.Ro * 1e3);
        fprintf(f, "    material: {convention: paper, C1_pa: %.17g, C2_pa: %.17g}\n", b->iab.C1,
                b->iab.C2);
        fprintf(f, "    pressure_min_kpa: %.17g\n    pressure_max_kpa: %.17g\n", b->p_min / 1e3,
                b->p_max / 1e3);
        fprintf(f, "    stretch_min: %.17g\n    stretch_max: %.17g\n", b->stretch_min,
                b->stretch_max);
        if (isfinite(b->rate_max)) fprintf(f, "    rate_max_kpa: %.17g\n", b->rate_max / 1e3);
    }
    if (!base) {
        fprintf(f, "model: {level: %s}\n", hp_level_name(level));
        return;
    }
    if (base->has_load) {
        /* The carried mass as the part of the head's it is (the caller raises the head's
         * mass when a fitted load exceeds it). */
        double g = sqrt(base->load.gravity[0] * base->load.gravity[0] +
                        base->load.gravity[1] * base->load.gravity[1] +
                        base->load.gravity[2] * base->load.gravity[2]);
        double frac = L->head.mass > 0 ? base->load.mass / L->head.mass : 1.0;
        fprintf(f, "load: {carried_fraction: %.17g, com_mm: ", frac > 1.0 ? 1.0 : frac);
        vec_mm(f, base->load.com);
        fprintf(f, ", gravity_dir: [%.17g, %.17g, %.17g], geometry: %s, tiebreak: %s",
                base->load.gravity[0] / g, base->load.gravity[1] / g, base->load.gravity[2] / g,
                hp_level_name(base->load_geometry),
                hp_load_tiebreak_name((hp_load_tiebreak)base->load_tiebreak));
        /* the contact law when not the default (a scene written before the key reads the same) */
        if (base->load.law != HP_LOAD_LAW_FEM)
            fprintf(f, ", law: %s", hp_load_law_name(base->load.law));
        fputs("}\n", f);
    }
    fprintf(f, "model: {level: %s, tolerance_mm: %.17g",
            base->level_load ? "load" : hp_level_name(level), base->level_tolerance * 1e3);
    if (base->has_auto_range)
        fprintf(f, ", auto_translation_mm: %.17g, auto_rotation_deg: %.17g", base->auto_trans * 1e3,
                base->auto_rot * HP_DEG_PER_RAD);
    fprintf(f,
            "}\nsolver: {backend: %s, tolerance: %.17g, max_iter: %d, max_time_s: %.17g, "
            "weight_mm_per_deg: %.17g",
            hp_backend_name(base->backend), base->tolerance, base->max_iter, base->max_time,
            base->weight_mm_per_deg);
    /* Written when it is not the default, so that a fitted scene plans as its base does. */
    if (base->restarts != HP_DEFAULT_RESTARTS) fprintf(f, ", restarts: %d", base->restarts);
    fprintf(f, "}\n");
    if (base->has_correction) {
        double c[6];
        hp_pose_to_clinical(base->correction, c);
        fprintf(f, "correction: {");
        for (int j = 0; j < 6; ++j) fprintf(f, "%s%s: %.17g", j ? ", " : "", hp_pose_key(j), c[j]);
        fprintf(f, "}\n");
    }
}

hp_error hp_calib_check_output(const char *path, const char *const *inputs, int n_inputs,
                               hp_diag *d)
{
    if (!path || (n_inputs > 0 && !inputs)) return hp_diag_set(d, HP_ERR_NULL, "NULL argument");
    for (int i = 0; i < n_inputs; ++i)
        if (inputs[i] && (strcmp(inputs[i], path) == 0 || same_file(inputs[i], path)))
            return hp_diag_set(d, HP_ERR_INVALID,
                               "%s: is an input of the fit; write the calibrated scene to "
                               "another file",
                               path);
    /* hp_calib_write_scene's rename replaces whatever the name holds: a FIFO someone reads, a device
     * node (as root even /dev/null), or a symbolic link the user may have meant to write
     * through. Only a regular file (or nothing) may be replaced. */
    struct stat st;
    if (lstat(path, &st) == 0) {
        if (S_ISLNK(st.st_mode))
            return hp_diag_set(d, HP_ERR_INVALID,
                               "%s: is a symbolic link: refused (name the file itself)", path);
        if (S_ISDIR(st.st_mode))
            return hp_diag_set(d, HP_ERR_INVALID, "%s: is a directory, not a file", path);
        if (!S_ISREG(st.st_mode))
            return hp_diag_set(d, HP_ERR_INVALID,
                               "%s: exists and is not a regular file (a device, FIFO or "
                               "socket): refused",
                               path);
    } else if (errno != ENOENT) {
        return hp_diag_set(d, HP_ERR_IO, "%s: %s", path, strerror(errno));
    }
    return HP_OK;
}

hp_error hp_calib_write_scene(const char *path, const hp_layout *L, hp_level level,
                              const hp_scene *base, const char *name, const char *const *inputs,
                              int n_inputs, hp_diag *d)
{
    if (!path || !L || !name || (n_inputs > 0 && !inputs))
        return hp_diag_set(d, HP_ERR_NULL, "NULL argument");
    hp_layout chk = *L; /* the full checks, on a copy: L is the caller's */
    hp_error e0 = hp_layout_prepare(&chk, d);
    if (e0 != HP_OK) return e0;
    if (!hp_level_is_geometry(level) && level != HP_LEVEL_AUTO)
        return hp_diag_set(d, HP_ERR_INVALID, "level: unknown");
    hp_error refused = hp_calib_check_output(path, inputs, n_inputs, d);
    if (refused) return refused;
    size_t len = strlen(path);
    char *tmp = malloc(len + 16);
    if (!tmp) return hp_diag_set(d, HP_ERR_NOMEM, "out of memory");
    snprintf(tmp, len + 16, "%s.tmpXXXXXX", path);
    int fd = mkstemp(tmp);
    if (fd < 0) {
        hp_error e = hp_diag_set(d, HP_ERR_IO, "%s: cannot create: %s", path, strerror(errno));
        free(tmp);
        return e;
    }
    FILE *f = fdopen(fd, "w");
    if (!f) {
        close(fd);
        unlink(tmp);
        free(tmp);
        return hp_diag_set(d, HP_ERR_IO, "%s: cannot write", path);
    }
    /* A scene is read in the C locale: under the host's comma locale "%.17g" wrote "1,5". */
    hp_c_numeric c;
    hpi_c_numeric_begin(&c);
    write_body(f, L, level, base, name);
    hpi_c_numeric_end(&c);
    int bad = fflush(f) != 0 || ferror(f) || fsync(fileno(f)) != 0;
    bad |= fclose(f) != 0;
    /* mkstemp makes the file 0600; a scene is an ordinary document. */
    if (!bad) bad = chmod(tmp, 0644) != 0;
    if (!bad) bad = rename(tmp, path) != 0;
    if (bad) {
        int er = errno;
        unlink(tmp);
        free(tmp);
        return hp_diag_set(d, HP_ERR_IO, "%s: cannot write: %s", path, strerror(er));
    }
    free(tmp);
    return HP_OK;
}
