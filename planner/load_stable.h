/* Internal: HOLD's stable member (load_stable.c, docs/load.md "Stable holds"): when the
 * tie-breaker's pick at a pose is not a stable hold, the cheapest stable member of the
 * holding family that the search finds. No allocation. */
#ifndef HP_PLANNER_LOAD_STABLE_H
#define HP_PLANNER_LOAD_STABLE_H

#include "planner/load_solve.h"

/* The stable hold (docs/load.md, "Stable holds"): the smallest eigenvalue of the holding
 * stiffness [N/mm, mm/degree units] HOLD's stable search asks of a hold. A plan's answer
 * meets the equilibrium to 1e-9 N (load_level.c), so the forward statics started at a hold
 * this stable moves the head by at most about 1e-9 N / margin = 1e-7 mm (or degree): ten
 * times inside the 1e-6 mm/deg at which the rest must confirm a REACHED answer, and eleven
 * orders of magnitude above the eigenvalue's rounding (~1e-12 N/mm at stiffnesses of tens
 * of N/mm). The plan's own verdict is that confirmation (K positive definite and the rest
 * within 1e-6 mm/deg), so a pick below the margin that the rest confirms stands. */
#define HP_LOAD_STABLE_MARGIN 1e-2
/* [m] The stable hold counts a bladder's stiffness only when its force outlasts this much of
 * the head moving away from it (force >= its normal stiffness times this), so that a contact
 * the stability relies on is not lost on the way to the rest or under the contact law's own
 * error: 1e6 times the 1e-7 mm the forward statics may move from an answer. At 1e-7 m the
 * supine scene's stable hold touched its forehead bladders with 1e-5 N, and the fitted
 * law's ±4.61 % band already left the head without a rest; at 1e-4 m it rests within
 * 0.36 mm. */
#define HP_LOAD_STABLE_CONTACT 1e-4

/* HOLD's stable member (docs/load.md, "Stable holds"): P[n] (in: the tie-breaker's pick,
 * holding the head at xi inside [lo, hi]) is kept when its holding stiffness's smallest
 * eigenvalue is at least HP_LOAD_STABLE_MARGIN (counting the bladders whose contact outlasts
 * HP_LOAD_STABLE_CONTACT); otherwise P gets the member of the holding family with the least
 * tie-breaker sum sum (P − t)² that the search finds among those that are at least that
 * stable: a scan of the family (load_solve.c, grid_forces: the tie-breaker's 3×3 grid of its
 * free pressures and its vertices, at most 9 + 112 points; where none is stable a 7×7 grid
 * and the vertices, at most 49 + 112) for the cheapest stable point c, then a bisection on
 * the segment of forces from the pick to c (the set is convex in the forces) for the stable
 * point nearest the pick, 10 halvings (2^-10 of the segment; each point's pressures solved
 * from the inner radii at the bracket's two ends); the cheapest stable point seen wins. F
 * gets its forces, *lam_min (may be NULL) its smallest eigenvalue (one 6×6 eigenproblem,
 * solved only when asked for). OK with P stable (P and F unchanged when the pick is);
 * UNREACHABLE when no point of the scans is stable, ERROR when the model fails (P and F
 * unchanged on both). Deterministic, no allocation, at most 282 scan points and 11 other
 * points whose pressures it solves (the scan's, 10 on the segment; the pick's inner radii
 * come from its own pressures, one forward-kinematics solve a carrying bladder), each one
 * tie-breaker sum and at most one stability test (a 6×6 Cholesky factorisation of
 * K − margin·I). */
hpi_load_solve_status hpi_load_stable_hold(const hp_load_model *M, const double xi[6],
                                           const double *lo, const double *hi, const double *target,
                                           double *P, double *F, double *lam_min);

/* hpi_load_stable_hold on the holding set HOLD formed at xi (hs: its bounds and target), with
 * HOLD's scan record rec (may be NULL, or not valid: the search scans the set itself). The
 * same answer: the replay finds the scan's c bit for bit and hands over its pressures (one
 * point fewer to solve); rec's sums may be carried on. */
hpi_load_solve_status hpi_load_stable_hold_set(const hp_load_hold_set *hs, hp_load_scan_rec *rec,
                                               const double xi[6], double *P, double *F,
                                               double *lam_min);

/* TEST-ONLY counts (inert unless a test reads them; summed over the process): the stable
 * searches that went past the pick's own test, the points of the set whose pressures they
 * solved outside the scan (the pick, the scan's point and the segment's), the stability
 * tests of a point (the scan's included), the 6×6 stiffness eigenproblems solved, and the
 * pressure-of-force solves of those points with their steps (hpi_test_pressure_counts). */
typedef struct hp_test_stable_counts {
    unsigned long searches, points, tests, eigen;
    unsigned long solves, steps; /* those points' pressure-of-force solves and their steps */
} hp_test_stable_counts;
void hpi_test_stable_counts(hp_test_stable_counts *out);

#endif
