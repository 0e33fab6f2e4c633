/* Internal: the sections of a scene file, each read from its yaml_tree node. */
#ifndef HP_SCENE_PARTS_H
#define HP_SCENE_PARTS_H

#include "headplan/hp_scene.h"
#include "scene/scene_read.h"

/* A bladder's material mapping {convention, C1_pa, C2_pa} or {convention, C10_pa, C01_pa}:
 * sets iab->C1, iab->C2 (paper convention); conv and written (may be NULL) get what the
 * file wrote. */
hp_error sp_material(const sr_ctx *c, const yt_node *node, const char *path, hp_iab *iab,
                     hp_material_convention *conv, double written[2]);

/* A bladder's radii, material and limits, each read from map or else from defaults (may be
 * NULL). With require = 0 (the bladder_defaults section itself) absent keys are skipped and
 * only the pairs present are cross-checked. Units: file mm, kPa -> b in m, Pa. */
hp_error sp_bladder_params(const sr_ctx *c, const yt_node *map, const char *path,
                           const yt_node *defaults, int require, hp_bladder *b);

/* The head mapping. */
hp_error sp_head(const sr_ctx *c, const yt_node *node, const char *path, hp_head *h);

/* The `bladders` list with `bladder_defaults` (may be NULL) into L->bladders, L->n; the head
 * must be set already (touch placement needs it). */
hp_error sp_bladders(const sr_ctx *c, const yt_node *list, const yt_node *defaults, hp_layout *L);

/* The single-bladder study (`bladder`) and the printed values (`paper_printed`). */
hp_error sp_study(const sr_ctx *c, const yt_node *node, hp_bladder_study *s);
hp_error sp_printed(const sr_ctx *c, const yt_node *node, hp_bladder_study *s);

/* The `load` section (head and layout already read). */
hp_error sp_load(const sr_ctx *c, const yt_node *node, hp_scene *s);

#endif
