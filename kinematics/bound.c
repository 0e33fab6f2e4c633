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
 * the smaller of the direct one and plane + ½A. The bound is the maximum over bladders.
 *
 * The same sizes bound one step of a solver, τ ↦ ξa + τΔ (hpi_kin_contact_step_bound):
 * |t| <= |ta| + |Δt| on the way, so |u| = |c − pivot − t| <= L + |ta| + |Δt| =: U; the
 * rates are constant, |ω| <= √2|Δθ| and |ω̇| <= (1 + √5)/4·|Δθ|²; then
 * |v| <= |ω|U + |Δt| =: V, |a| <= (|ω|² + |ω̇|)U + 2|ω||Δt| =: A, the path stays within V
 * of c'(0), and f(1) − f(0) − f'(0) (f'(0) = J·Δ) is at most ½ max|f''|: ½A on the plane,
 * ½(V²/(Rmin + ρa − V) + A) on the surface while V < ρa. */
#include "kin_internal.h"
#include "kin_geom.h"
#include "kinematics/names.h"
#include "common/units.h"

#include <math.h>

typedef struct sizes {
    double delta, V, A, rmin, rho0;
} sizes;

/* Sizes of bladder k's back-transformed centre c'(τ) along a straight pose path: lev >=
 * |c − pivot|, |t| <= ta at its start, the translation moves by at most dt (m), the
 * rotation has angular speed <= om and acceleration <= omd. Then |u| = |c − pivot − t| <=
 * lev + ta + dt =: U, |v| <= om·U + dt and |a| <= (om² + omd)·U + 2·om·dt (header). */
static sizes sizes_along(const hp_geom *G, int k, double lev, double ta, double dt, double om,
                         double omd, double rmin)
{
    double U = lev + ta + dt;
    sizes s;
    s.delta = fmin(2.0, om) * lev + ta + dt;
    s.V = om * U + dt;
    s.A = (om * om + omd) * U + 2.0 * om * dt;
    s.rmin = rmin;
    s.rho0 = G->rho0[k];
    return s;
}

/* The path from the nominal pose (header): ta = 0, dt = T. */
static sizes path_sizes(const hp_geom *G, int k, double T, double rot)
{
    const double *w = G->arm[k];
    double om = rot * sqrt(1.0 + 2.0 * rot / (3.0 * sqrt(3.0)));
    double omd = 0.25 * (1.0 + sqrt(5.0)) * rot * rot;
    return sizes_along(G, k, hypot(hypot(w[0], w[1]), w[2]), 0.0, T, om, omd,
                       hpi_kin_head_min_curvature_radius(&G->head));
}

/* ½·max|f''| for f(τ) = d(c'(τ)), d the distance to the convex head, when the path stays
 * at least rho0 − delta > 0 from it (d is 1-Lipschitz); infinity otherwise. */
static double surface_remainder(const sizes *s)
{
    if (!(s->delta < s->rho0)) return INFINITY;
    return 0.5 * (s->V * s->V / (s->rmin + s->rho0 - s->delta) + s->A);
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
    return fmin(plane_bound(s) + 0.5 * s->A, surface_remainder(s));
}

hp_error hpi_contact_error_bound_g(const hp_layout *L, const hp_geom *G, hp_level level,
                                   double trans, double rot, double *bound)
{
    if (!L || !G || !bound) return HP_ERR_NULL;
    if (!(trans >= 0) || !isfinite(trans) || !(rot >= 0) || !isfinite(rot)) return HP_ERR_INVALID;
    if (!hp_level_is_geometry(level)) return HP_ERR_INVALID;
    double worst = 0.0;
    if (level != HP_LEVEL_SURFACE)
        for (int k = 0; k < L->n; ++k) {
            sizes s = path_sizes(G, k, trans, rot);
            worst = fmax(worst, level == HP_LEVEL_LINEAR ? linear_bound(&s) : plane_bound(&s));
        }
    *bound = worst;
    return HP_OK;
}

hp_error hpi_contact_auto_g(const hp_layout *L, const hp_geom *G, double tol, double trans,
                            double rot, hp_level *level)
{
    if (!L || !G || !level) return HP_ERR_NULL;
    if (!(tol >= 0) || !isfinite(tol)) return HP_ERR_INVALID;
    /* The geometries cheapest first; the last is exact (bound 0 <= tol), so one is chosen. */
    for (int i = 0; i < hpi_level_n_geometries; ++i) {
        double b;
        hp_error err = hpi_contact_error_bound_g(L, G, hpi_level_geometries[i], trans, rot, &b);
        if (err) return err;
        if (b <= tol) {
            *level = hpi_level_geometries[i];
            return HP_OK;
        }
    }
    return HP_ERR_INVALID; /* not reached: the exact geometry's bound is 0 */
}

hp_error hp_contact_error_bound(const hp_layout *L, hp_level level, double trans, double rot,
                                double *bound)
{
    if (!L || !bound) return HP_ERR_NULL;
    hp_geom G;
    if (hpi_geom_derive(L, &G, NULL) != HP_OK) return HP_ERR_INVALID;
    return hpi_contact_error_bound_g(L, &G, level, trans, rot, bound);
}

hp_error hp_contact_auto(const hp_layout *L, double tol, double trans, double rot, hp_level *level)
{
    if (!L || !level) return HP_ERR_NULL;
    hp_geom G;
    if (hpi_geom_derive(L, &G, NULL) != HP_OK) return HP_ERR_INVALID;
    return hpi_contact_auto_g(L, &G, tol, trans, rot, level);
}

static double l1(const double v[3]) { return fabs(v[0]) + fabs(v[1]) + fabs(v[2]); }

hp_error hpi_kin_contact_step_bound(const hp_layout *L, const hp_geom *G, hp_level level,
                                    const double xi[6], const double dxi[6], const double *rho,
                                    double *bound)
{
    if (!L || !G || !xi || !dxi || !bound || (level == HP_LEVEL_SURFACE && !rho))
        return HP_ERR_NULL;
    if (!hp_level_is_geometry(level)) return HP_ERR_INVALID;
    for (int i = 0; i < 6; ++i)
        if (!isfinite(xi[i]) || !isfinite(dxi[i])) return HP_ERR_INVALID;
    /* Rates along the path are the constant dxi. With R = Rz(γ)Ry(β)Rx(α) the angular
     * velocity is γ' e_z + β' Rz e_y + α' RzRy e_x, whose only non-orthogonal pair
     * (e_z, RzRy e_x) has the product −sin β, so |ω|² <= |dθ|² + 2|α'γ'| <= 2|dθ|²; its
     * derivative is bounded as from the nominal pose, by (1 + √5)/4·|dθ|². Every length
     * is taken as its 1-norm, an upper bound of the 2-norm without a square root: a
     * solver asks this of steps whose remainder is far below any rounding. */
    double ta = l1(xi), dt = l1(dxi), dth = l1(dxi + 3);
    double om = sqrt(2.0) * dth, omd = 0.25 * (1.0 + sqrt(5.0)) * dth * dth;
    double rmin = hpi_kin_head_min_curvature_radius(&G->head);
    for (int k = 0; k < L->n; ++k) {
        if (level == HP_LEVEL_LINEAR) {
            bound[k] = 0.0; /* rho is affine in the pose */
            continue;
        }
        sizes s = sizes_along(G, k, l1(G->arm[k]), ta, dt, om, omd, rmin);
        if (level == HP_LEVEL_PLANE) {
            bound[k] = 0.5 * s.A; /* f = nᵀ(c' − p): f'' = nᵀa */
            continue;
        }
        /* Along this path |c'(τ) − c'(0)| <= V, so V stands for delta and rho[k] for the
         * start's distance. */
        s.delta = s.V;
        s.rho0 = rho[k];
        bound[k] = surface_remainder(&s);
    }
    return HP_OK;
}

/* The curvature of each distance over a ball of poses (hpi_kin_contact_ball_curvature, the
 * fit's certificate). At a pose p and along a unit scaled direction v (translation part
 * v_t in mm, rotation part v_θ in degrees, |v_t|² + |v_θ|² = 1) the path τ ↦ p + τv has
 * the constant rates |ṫ| = a|v_t| (a = 1 mm in m) and |θ̇| = b|v_θ| (b = 1° in rad), so
 * (step bound above) |ω| <= √2·b|v_θ|, |ω̇| <= φ·b²|v_θ|² (φ = (1 + √5)/4), and with
 * U >= |c − pivot − t| on the ball
 *   |v_c| <= √2·bU|v_θ| + a|v_t| <= √(2b²U² + a²) =: V1          (Cauchy–Schwarz),
 *   |a_c| <= (2 + φ)b²U|v_θ|² + 2√2·ab|v_θ||v_t| <= (2 + φ)b²U + √2·ab =: A1.
 * f'' = vᵀ∇²ρ v is nᵀa_c at the plane level, and v_cᵀ∇²d v_c + ∇dᵀa_c at the surface
 * level, where ∇²d has eigenvalues in [0, 1/(Rmin + d)] outside the convex head and the
 * distance on the ball is at least ρ(centre) − V1·r (d is 1-Lipschitz and c' moves at most
 * V1 per unit of scaled path). A symmetric matrix's spectral norm is its largest |vᵀHv|,
 * so h_k bounds ‖∇²ρ_k‖ in mm per scaled unit² everywhere on the ball. */
hp_error hpi_kin_contact_ball_curvature(const hp_layout *L, const hp_geom *G, hp_level level,
                                        const double xc[6], double r, const double *rho, double *h)
{
    if (!L || !G || !xc || !h || (level == HP_LEVEL_SURFACE && !rho)) return HP_ERR_NULL;
    if (!hp_level_is_geometry(level)) return HP_ERR_INVALID;
    if (!(r >= 0) || !isfinite(r)) return HP_ERR_INVALID;
    for (int i = 0; i < 6; ++i)
        if (!isfinite(xc[i])) return HP_ERR_INVALID;
    const double a = 1.0 / HP_MM_PER_M, b = HP_RAD_PER_DEG;
    const double phi = 0.25 * (1.0 + sqrt(5.0));
    /* |t| on the ball: the centre's translation plus r mm. */
    double T = sqrt(xc[0] * xc[0] + xc[1] * xc[1] + xc[2] * xc[2]) + r * a;
    double rmin = hpi_kin_head_min_curvature_radius(&G->head);
    for (int k = 0; k < L->n; ++k) {
        if (level == HP_LEVEL_LINEAR) {
            h[k] = 0.0;
            continue;
        }
        const double *w = G->arm[k]; /* metres: its squares neither overflow nor underflow */
        double U = sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]) + T;
        /* A unit path: its speed and acceleration bounds V1, A1 (above), the distance at
         * the centre, and the most the path can approach the head over the ball, V1·r:
         * surface_remainder's ½·max|f''| is then half of what is sought. */
        sizes sz;
        sz.V = sqrt(2.0 * b * b * U * U + a * a);
        sz.A = (2.0 + phi) * b * b * U + sqrt(2.0) * a * b;
        sz.delta = sz.V * r;
        sz.rmin = rmin;
        sz.rho0 = rho ? rho[k] : 0.0;
        double hk = level == HP_LEVEL_SURFACE ? 2.0 * surface_remainder(&sz) : sz.A;
        if (!(hk >= 0)) hk = INFINITY; /* a NaN distance */
        /* The rounding of these few operations (a few ulps) is far below the slack of each
         * inequality; 1e-12 covers it. */
        h[k] = hk * HP_MM_PER_M * (1.0 + 1e-12);
    }
    return HP_OK;
}
