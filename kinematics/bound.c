/* Error bounds of the linear and plane levels against the exact surface distance, and the
 * automatic choice of level.
 *
 * Sizes: T = |t| (translation norm, m) and θ = |(pitch, roll, yaw)|₂ <= rot (rad).
 * w = c − pivot, L = |w|, n the nominal normal, ρ0 the nominal distance, Rmin the smallest
 * radius of curvature of the head. Follow the straight path τ ↦ τξ, τ in [0, 1]:
 *   c'(τ) = R(τ)ᵀ(w − τt) + pivot,  R(τ) = Rz(τγ)Ry(τβ)Rx(τα).
 * Angular velocity (space frame) ω = γ e_z + β Rz e_y + α RzRy e_x, so
 *   |ω|² = |θ|² − 2αγ sin(τβ) <= rot²(1 + 2rot/(3√3))            (|αβγ| <= (rot/√3)³),
 *   ω̇ = βγ e_z×Rz e_y + α(γ e_z + β Rz e_y)×RzRy e_x, |ω̇| <= |βγ| + |α|√(β²+γ²)
 *      <= (1 + √5)/4 · rot².
 * Hence ‖R − I‖ <= min(2, |ω|max), and with v = dc'/dτ, a = d²c'/dτ²:
 *   δ = |c' − c| <= ‖R − I‖·L + T,
 *   |v| <= |ω|(L + T) + T =: V,   |a| <= (|ω|² + |ω̇|)(L + T) + 2|ω|T =: A.
 * Outside a convex head the distance d has Hessian eigenvalues 0 and κ/(1 + dκ)
 * <= 1/(Rmin + d), and d >= ρ0 − δ on the way (d is 1-Lipschitz). Taylor with remainder:
 *   plane − surface = nᵀδ + ρ0 − d(c + δ):     |·| <= ½δ²/(Rmin + ρ0 − δ)   (δ < ρ0),
 *   linear − surface = f(0) + f'(0) − f(1), f(τ) = d(c'(τ)), f'' = vᵀ∇²d v + ∇dᵀa:
 *                                             |·| <= ½(V²/(Rmin + ρ0 − δ) + A),
 *   linear − plane: f_plane'' = nᵀa,           |·| <= ½A,
 * and always |plane − surface| <= 2δ (both sides 1-Lipschitz in c'). The linear bound is
 * the smaller of the direct one and plane + ½A. The bound is the maximum over bladders. */
#include "kin_internal.h"
#include "kin_geom.h"

#include <math.h>

typedef struct sizes {
    double delta, V, A, rmin, rho0;
} sizes;

static sizes path_sizes(const hp_layout *L, const hp_geom *G, int k, double T, double rot)
{
    double w[3];
    for (int i = 0; i < 3; ++i) w[i] = L->bladders[k].center[i] - L->pivot[i];
    double lev = hypot(hypot(w[0], w[1]), w[2]);
    double om = rot * sqrt(1.0 + 2.0 * rot / (3.0 * sqrt(3.0)));
    double omd = 0.25 * (1.0 + sqrt(5.0)) * rot * rot;
    sizes s;
    s.delta = fmin(2.0, om) * lev + T;
    s.V = om * (lev + T) + T;
    s.A = (om * om + omd) * (lev + T) + 2.0 * om * T;
    s.rmin = hp_kin_head_min_curvature_radius(&G->head);
    s.rho0 = G->rho0[k];
    return s;
}

static double plane_bound(const sizes *s)
{
    double lip = 2.0 * s->delta;
    if (s->delta < s->rho0)
        return fmin(lip, 0.5 * s->delta * s->delta / (s->rmin + s->rho0 - s->delta));
    return lip;
}

static double linear_bound(const sizes *s)
{
    double via_plane = plane_bound(s) + 0.5 * s->A;
    if (s->delta < s->rho0)
        return fmin(via_plane, 0.5 * (s->V * s->V / (s->rmin + s->rho0 - s->delta) + s->A));
    return via_plane;
}

hp_error hp_contact_error_bound_g(const hp_layout *L, const hp_geom *G, hp_level level,
                                  double trans, double rot, double *bound)
{
    if (!L || !G || !bound) return HP_ERR_NULL;
    if (!(trans >= 0) || !isfinite(trans) || !(rot >= 0) || !isfinite(rot))
        return HP_ERR_INVALID;
    if (level != HP_LEVEL_LINEAR && level != HP_LEVEL_PLANE && level != HP_LEVEL_SURFACE)
        return HP_ERR_INVALID;
    double worst = 0.0;
    if (level != HP_LEVEL_SURFACE)
        for (int k = 0; k < L->n; ++k) {
            sizes s = path_sizes(L, G, k, trans, rot);
            worst = fmax(worst, level == HP_LEVEL_LINEAR ? linear_bound(&s) : plane_bound(&s));
        }
    *bound = worst;
    return HP_OK;
}

hp_error hp_contact_auto_g(const hp_layout *L, const hp_geom *G, double tol, double trans,
                           double rot, hp_level *level)
{
    if (!L || !G || !level) return HP_ERR_NULL;
    if (!(tol >= 0) || !isfinite(tol)) return HP_ERR_INVALID;
    static const hp_level order[2] = {HP_LEVEL_LINEAR, HP_LEVEL_PLANE};
    for (int i = 0; i < 2; ++i) {
        double b;
        hp_error err = hp_contact_error_bound_g(L, G, order[i], trans, rot, &b);
        if (err) return err;
        if (b <= tol) {
            *level = order[i];
            return HP_OK;
        }
    }
    *level = HP_LEVEL_SURFACE;
    return HP_OK;
}

hp_error hp_contact_error_bound(const hp_layout *L, hp_level level, double trans, double rot,
                                double *bound)
{
    if (!L || !bound) return HP_ERR_NULL;
    hp_geom G;
    if (hp_geom_derive(L, &G, NULL) != HP_OK) return HP_ERR_INVALID;
    return hp_contact_error_bound_g(L, &G, level, trans, rot, bound);
}

hp_error hp_contact_auto(const hp_layout *L, double tol, double trans, double rot,
                         hp_level *level)
{
    if (!L || !level) return HP_ERR_NULL;
    hp_geom G;
    if (hp_geom_derive(L, &G, NULL) != HP_OK) return HP_ERR_INVALID;
    return hp_contact_auto_g(L, &G, tol, trans, rot, level);
}
