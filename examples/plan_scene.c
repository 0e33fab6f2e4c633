/* Plan a scene's correction with the installed headplan library (the README's example).
 *
 *   plan_scene SCENE.yaml
 *
 * Loads the scene, asks the library for the planner settings the scene states (the same
 * call `headplan solve` makes, so both plan at the same contact level with the same
 * solver), plans the scene's correction from rest and prints the status and every bladder's pressure
 * with 17 significant digits (enough to read back the same double). Every return code is
 * checked and the planner, the only thing allocated, is freed. Exit status: 0 reached,
 * 1 any other outcome, 2 an error. Units: the library speaks SI (m, rad, Pa). The scene
 * holds no pointers and is small (4.8 KB), so it lives on the stack. */
#include <headplan/headplan.h>

#include <stdio.h>

int main(int argc, char **argv)
{
    if (argc != 2) {
        fprintf(stderr, "usage: plan_scene SCENE.yaml\n");
        return 2;
    }
    hp_diag d;
    hp_scene sc;
    hp_settings s;
    hp_planner *p = NULL;
    int rc = 2;
    if (hp_scene_load(argv[1], &sc, &d) != HP_OK) goto fail;
    if (!sc.has_correction) {
        fprintf(stderr, "plan_scene: %s states no correction\n", argv[1]);
        goto done;
    }
    if (hp_scene_settings(&sc, &s, &d) != HP_OK) goto fail;
    /* One plan from rest, as `headplan solve` makes: no previous cycle whose pressures a
     * rate limit could bound. A control loop keeps them on (the scene's rate_max). */
    s.use_rate_limits = 0;
    if (hp_planner_create(&sc.layout, &s, &p, &d) != HP_OK) goto fail;

    hp_result r;
    if (hp_plan(p, sc.correction, &r) != HP_OK) { /* no allocation, no output */
        fprintf(stderr, "plan_scene: hp_plan refused its arguments\n");
        goto done;
    }
    printf("status %s\n", hp_status_name(r.status));
    if (r.status != HP_STATUS_REACHED) /* an answer explains itself, a failure says why */
        printf("message %s\n", hp_planner_message(p));
    for (int k = 0; k < r.n; ++k)
        printf("%s %.17g\n", sc.layout.bladders[k].name, r.bladders[k].pressure);
    rc = r.status == HP_STATUS_REACHED ? 0 : 1;
    goto done;
fail:
    fprintf(stderr, "plan_scene: %s\n", d.text);
done:
    hp_planner_destroy(p); /* safe on NULL */
    return rc;
}
