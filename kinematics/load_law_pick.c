/* A load model's contact law, chosen after creation (load_law_pick.h). */
#include "kinematics/load_law_pick.h"
#include "kinematics/load_internal.h"

hp_claw_law hpi_load_model_law(const hp_load_model *M) { return M ? M->law : HP_CLAW_LAW_CAP; }

hp_error hpi_load_model_set_law(hp_load_model *M, hp_claw_law law)
{
    if (!M) return HP_ERR_NULL;
    if (law != HP_CLAW_LAW_CAP && law != HP_CLAW_LAW_FEM) return HP_ERR_INVALID;
    /* The per-bladder data the fitted law reads (M->claw) is derived at setup for either
     * law, so the switch is this one field. */
    M->law = law;
    return HP_OK;
}

hp_error hpi_load_fem_domain_at(const hp_load_model *M, const double xi[6], const double *P,
                                int *bladder, hp_claw_domain *group)
{
    *bladder = -1;
    *group = HP_CLAW_IN;
    double ratio[HP_MAX_BLADDERS];
    hp_error err = hp_load_indentation(M, xi, P, ratio);
    if (err) return err;
    for (int k = 0; k < M->layout.n; ++k) {
        if (!(P[k] > 0.0 && ratio[k] > 0.0)) continue; /* carries nothing */
        double ro;
        if ((err = hp_load_radius(M, k, P[k], &ro, NULL))) return err;
        hp_claw_domain g = hpi_claw_fem_domain(&M->claw[k], P[k], ro, ro * (1.0 - ratio[k]));
        if (g != HP_CLAW_IN) {
            *bladder = k;
            *group = g;
            return HP_OK;
        }
    }
    return HP_OK;
}
