/* The rate window ends' fast path: the knots of hp_static_bounds (where a stand-in and a
 * root find's start come from) against the exact bounds.
 *
 * 1. Every window of the loop benchmark's rate (500 Pa a plan) anywhere in the static
 *    pressure range gets a stand-in at each end that is a bound, so setting the plan's
 *    bounds up solves no end (a stand-in window too narrow to use, or a missing stand-in,
 *    would solve both ends of that bladder at once: the plans that made the loop
 *    benchmark's p99.9). Each stand-in lies inside its exact bound (the eager bounds of
 *    hpi_setup_cycle_bounds_memo). Half the draws start with an empty memo, half with the
 *    memo of windows elsewhere in the range (as after a jump): a remembered bound far from
 *    its end is not taken as the stand-in where a knot lies nearer (taken, it crossed the
 *    other end's: 12 246 of 30 568 ends solved at set-up).
 * 2. The fast path gives the reference's ends bit for bit: bounds set up with stand-ins and
 *    then every end resolved (hpi_setup_rate_resolve) equal the eager bounds (the same
 *    radii, outer radii, flags and errors) when both start from equal memos, along a seeded
 *    chain of previous pressures (uniform in the static range, the limits, a hair inside and
 *    outside them (the next doubles), 0, the knots' own pressures) and rates (log-uniform
 *    1e-3 Pa .. 20 kPa, and 500 Pa).
 * 3. A window end far from the last bound solved for it (a jump of the previous pressure
 *    anywhere in the static range, as the step trace's new target makes) starts from the
 *    knots' interpolant and spends at most 3.1 closed-form pressure evaluations on average
 *    (hpi_test_rate_bound_evals, a deterministic count; measured 2.90 from the quintic
 *    interpolant, 3.61 from the cubic, 4.15 when a start below the root evaluated 2·Ri again
 *    for its bracket's upper end, 4.64 when the nudge evaluated again the radii the root
 *    find had looked at and 8.14 when it started from the far memo); every such bound holds
 *    exactly (fabs(P − P_prev) <= rate with P from hp_iab_ik at the bound). Bounds set up
 *    without a memo (hpi_setup_cycle_bounds) stay the cold root find's, bit for bit
 *    (tests/planner/test_rate_bounds.c).
 *    The start itself (hpi_setup_knot_guess, the quintic Hermite interpolant of ri(P) through
 *    the knots' radii, slopes and curvatures) lies within 1e-9 of the FK root (hp_iab_fk_limit)
 *    over every bladder's knot range, and at least 100 times nearer than the cubic through the
 *    radii and slopes alone, written out here as the reference (test_knot_guess_near_root).
 * 4. The knots' bracket of a window (hpi_setup_rate_surely_out, and before any bound is set
 *    hpi_setup_rate_surely_left) calls a radius outside only when it is
 *    (test_surely_out_is_sure).
 * 5. A bladder's rate window is worked out once a plan (hpi_setup_rate_windows, into
 *    hp_problem): the lazy set-up, the knots' bracket and every resolve after it read it and
 *    work out none of their own (hpi_test_rate_windows, a deterministic count); the
 *    bounds are the eager ones bit for bit (2.). A whole plan works out each window once too
 *    (tests/planner/test_rate_bounds.c, the measured step trace).
 * 6. The stand-ins a set-up keeps (hp_rate_stand) and takes again for windows that move by
 *    a reading's noise lie inside their exact bounds, leave the resolved bounds the eager
 *    ones bit for bit, and are seldom made anew (test_kept_stand_ins_serve).
 * 7. A bladder at or near a static pressure limit (its window reaching past it) takes the
 *    set-up's short way too: its far end a kept stand-in, its near end the static bounds
 *    bit for bit (test_static_end_stand_ins). */
#include "support/test_util.h"
#include "support/layout_fixture.h"
#include "planner/problem_setup.h"
#include "common/units.h"

/* The default layout with every rate_max = rate (NAN: as the layout has it) and its static
 * bounds. */
static void fixture(hp_layout *L, hp_static_bounds *sb, double rate)
{
    assert_int_equal(lf_layout(L), HP_OK);
    if (!isnan(rate))
        for (int k = 0; k < L->n; ++k) L->bladders[k].rate_max = rate;
    assert_int_equal(hpi_setup_static_bounds(L, sb, NULL), HP_OK);
}

/* A pressure uniform over bladder k's static interval. */
static double uniform_p(const hp_static_bounds *sb, int k, uint64_t *seed)
{
    double u = 0.5 * (lf_uniform(seed) + 1.0);
    return sb->p_lo[k] + u * (sb->p_hi[k] - sb->p_lo[k]);
}

/* Bladder k's previous pressure for draw kind `pick`: uniform, the limits and the doubles
 * next to them on both sides, 0, a knot's pressure. */
static double draw_pressure(const hp_static_bounds *sb, int k, uint64_t *seed)
{
    double lo = sb->p_lo[k], hi = sb->p_hi[k];
    int pick = (int)(test_rng_next(seed) % 12);
    switch (pick) {
    case 0: return lo;
    case 1: return hi;
    case 2: return nextafter(lo, INFINITY);
    case 3: return nextafter(hi, -INFINITY);
    case 4: return nextafter(lo, -INFINITY);
    case 5: return nextafter(hi, INFINITY);
    case 6: return 0.0;
    case 7: return sb->knot_p[k][test_rng_next(seed) % HP_RATE_KNOTS];
    default: return uniform_p(sb, k, seed);
    }
}

/* The bounds of a and b and their flags (la, lb low; ha, hb high) equal bit for bit. */
static void same_bounds(int n, const hp_problem *a, const hp_problem *b, const unsigned *la,
                        const unsigned *lb, const unsigned *ha, const unsigned *hb)
{
    for (int k = 0; k < n; ++k) {
        assert_true(memcmp(&a->ri_lo_si[k], &b->ri_lo_si[k], sizeof(double)) == 0);
        assert_true(memcmp(&a->ri_hi_si[k], &b->ri_hi_si[k], sizeof(double)) == 0);
        assert_true(memcmp(&a->ro_lo[k], &b->ro_lo[k], sizeof(double)) == 0);
        assert_true(memcmp(&a->ro_hi[k], &b->ro_hi[k], sizeof(double)) == 0);
        assert_int_equal(la[k], lb[k]);
        assert_int_equal(ha[k], hb[k]);
    }
}

/* The memo mz of the bounds of windows elsewhere (previous pressures uniform over each
 * bladder's range, as after a jump); pe and the flags are scratch. */
static void memo_elsewhere(const hp_layout *L, const hp_static_bounds *sb, uint64_t *seed,
                           hp_rate_memo *mz, hp_problem *pe, unsigned *le, unsigned *he)
{
    double Q[HP_MAX_BLADDERS];
    for (int k = 0; k < L->n; ++k) Q[k] = uniform_p(sb, k, seed);
    assert_int_equal(hpi_setup_cycle_bounds_memo(L, sb, Q, 1, mz, pe, le, he, NULL), HP_OK);
}

/* The bounds around P set up lazily into pz (memo mz, kept stand-ins st: may be NULL; the
 * set-up's state into *z) and eagerly into pe (memo me of its own), both without error. */
static void both_setups(const hp_layout *L, const hp_static_bounds *sb, const double *P,
                        hp_rate_memo *mz, hp_rate_stand *st, hp_rate_memo *me, hp_rate_lazy *z,
                        hp_problem *pz, unsigned *lz, unsigned *hz, hp_problem *pe, unsigned *le,
                        unsigned *he)
{
    memcpy(pz->p_prev, P, sizeof pz->p_prev);
    hpi_setup_rate_windows(L, pz);
    *z = (hp_rate_lazy){
        .L = L, .b = sb, .memo = mz, .stand = st, .pb = pz, .lo_flags = lz, .hi_flags = hz};
    assert_int_equal(hpi_setup_cycle_bounds_lazy(z, NULL), HP_OK);
    assert_int_equal(hpi_setup_cycle_bounds_memo(L, sb, P, 1, me, pe, le, he, NULL), HP_OK);
}

/* Lazy bounds around P into pb (memo mz) with every stand-in then resolved. */
static hp_error lazy_all(const hp_layout *L, const hp_static_bounds *sb, hp_rate_memo *mz,
                         const double *P, hp_problem *pb, unsigned *lof, unsigned *hif)
{
    memcpy(pb->p_prev, P, sizeof pb->p_prev);
    hpi_setup_rate_windows(L, pb);
    hp_rate_lazy z = {.L = L, .b = sb, .memo = mz, .pb = pb, .lo_flags = lof, .hi_flags = hif};
    hp_error e = hpi_setup_cycle_bounds_lazy(&z, NULL);
    if (e != HP_OK) return e;
    for (int k = 0; k < L->n; ++k) assert_true(hpi_setup_rate_resolve(&z, k, 3u));
    assert_false(hpi_setup_rate_pending(&z));
    return HP_OK;
}

static void test_loop_windows_have_stand_ins(void **state)
{
    (void)state;
    hp_layout L;
    static hp_static_bounds sb;
    fixture(&L, &sb, 500.0);
    uint64_t seed = 0x57a2d;
    long ends = 0, solved = 0;
    for (int t = 0; t < 2000; ++t) {
        double P[HP_MAX_BLADDERS];
        for (int k = 0; k < L.n; ++k) P[k] = uniform_p(&sb, k, &seed);
        hp_rate_memo mz, me;
        memset(&mz, 0, sizeof mz);
        hp_problem pz, pe;
        unsigned lz[HP_MAX_BLADDERS], hz[HP_MAX_BLADDERS], le[HP_MAX_BLADDERS], he[HP_MAX_BLADDERS];
        /* odd draws: the memo holds the bounds of windows elsewhere (a jump) */
        if (t % 2) memo_elsewhere(&L, &sb, &seed, &mz, &pe, le, he);
        me = mz;
        memcpy(pz.p_prev, P, sizeof pz.p_prev);
        hpi_setup_rate_windows(&L, &pz);
        hp_rate_lazy z = {
            .L = &L, .b = &sb, .memo = &mz, .pb = &pz, .lo_flags = lz, .hi_flags = hz};
        unsigned long s0 = hpi_test_rate_bound_solves();
        assert_int_equal(hpi_setup_cycle_bounds_lazy(&z, NULL), HP_OK);
        solved += (long)(hpi_test_rate_bound_solves() - s0);
        assert_int_equal(hpi_setup_cycle_bounds_memo(&L, &sb, P, 1, &me, &pe, le, he, NULL), HP_OK);
        for (int k = 0; k < L.n; ++k) {
            ends += z.lo[k] + z.hi[k];
            /* a stand-in lies inside the exact bound */
            assert_true(pz.ro_lo[k] >= pe.ro_lo[k]);
            assert_true(pz.ro_hi[k] <= pe.ro_hi[k]);
            if (z.lo[k]) assert_true(pz.ro_lo[k] > pe.ro_lo[k]);
            if (z.hi[k]) assert_true(pz.ro_hi[k] < pe.ro_hi[k]);
        }
    }
    print_message("500 Pa windows: %ld ends set up as stand-ins, %ld solved at set-up\n", ends,
                  solved);
    assert_true(ends > 20000); /* the sweep exercised the stand-ins */
    assert_int_equal(solved, 0);
}

static void test_fast_ends_equal_reference(void **state)
{
    (void)state;
    hp_layout L;
    static hp_static_bounds sb;
    fixture(&L, &sb, NAN);
    hp_rate_memo mz, me; /* equal memos, each kept along its own path */
    memset(&mz, 0, sizeof mz);
    memset(&me, 0, sizeof me);
    uint64_t seed = 0xb17b17;
    long compared = 0, refused = 0;
    for (int t = 0; t < 4000; ++t) {
        double P[HP_MAX_BLADDERS];
        for (int k = 0; k < L.n; ++k) {
            P[k] = draw_pressure(&sb, k, &seed);
            L.bladders[k].rate_max = t % 3 == 0
                                         ? 500.0
                                         : pow(10.0, -3.0 + 7.3 * 0.5 * (lf_uniform(&seed) + 1.0));
        }
        hp_problem pz, pe;
        unsigned lz[HP_MAX_BLADDERS], hz[HP_MAX_BLADDERS], le[HP_MAX_BLADDERS], he[HP_MAX_BLADDERS];
        hp_error ez = lazy_all(&L, &sb, &mz, P, &pz, lz, hz);
        hp_error ee = hpi_setup_cycle_bounds_memo(&L, &sb, P, 1, &me, &pe, le, he, NULL);
        assert_int_equal(ez, ee);
        if (ee != HP_OK) {
            /* a refused draw may leave the memos apart (the eager path stops at the first
             * bladder without a radius): start both again */
            memset(&mz, 0, sizeof mz);
            memset(&me, 0, sizeof me);
            ++refused;
            continue;
        }
        for (int k = 0; k < L.n; ++k) {
            if (memcmp(&pz.ri_lo_si[k], &pe.ri_lo_si[k], sizeof(double)) ||
                memcmp(&pz.ri_hi_si[k], &pe.ri_hi_si[k], sizeof(double)) ||
                memcmp(&pz.ro_lo[k], &pe.ro_lo[k], sizeof(double)) ||
                memcmp(&pz.ro_hi[k], &pe.ro_hi[k], sizeof(double)) || lz[k] != le[k] ||
                hz[k] != he[k]) {
                print_error("draw %d bladder %d (P %.17g, rate %.17g): lazy %.17g..%.17g "
                            "(%u, %u), eager %.17g..%.17g (%u, %u)\n",
                            t, k, P[k], L.bladders[k].rate_max, pz.ri_lo_si[k], pz.ri_hi_si[k],
                            lz[k], hz[k], pe.ri_lo_si[k], pe.ri_hi_si[k], le[k], he[k]);
                fail();
            }
            ++compared;
        }
    }
    print_message("fast path: %ld bladders' bounds equal the eager ones bit for bit, %ld draws "
                  "refused by both\n",
                  compared, refused);
    assert_true(compared > 20000);
}

static void test_far_end_starts_near(void **state)
{
    (void)state;
    hp_layout L;
    static hp_static_bounds sb;
    fixture(&L, &sb, 500.0);
    uint64_t seed = 0xf1257;
    unsigned long solves = 0, evals = 0;
    for (int t = 0; t < 2000; ++t) {
        double P[HP_MAX_BLADDERS], Q[HP_MAX_BLADDERS];
        for (int k = 0; k < L.n; ++k) {
            P[k] = uniform_p(&sb, k, &seed);
            Q[k] = uniform_p(&sb, k, &seed);
        }
        hp_rate_memo memo;
        memset(&memo, 0, sizeof memo);
        hp_problem pb;
        unsigned lof[HP_MAX_BLADDERS], hif[HP_MAX_BLADDERS];
        /* the memo's last bounds around Q, then a jump to P (the step trace's new target) */
        assert_int_equal(hpi_setup_cycle_bounds_memo(&L, &sb, Q, 1, &memo, &pb, lof, hif, NULL),
                         HP_OK);
        unsigned long s0 = hpi_test_rate_bound_solves(), e0 = hpi_test_rate_bound_evals();
        hp_error e = hpi_setup_cycle_bounds_memo(&L, &sb, P, 1, &memo, &pb, lof, hif, NULL);
        solves += hpi_test_rate_bound_solves() - s0;
        evals += hpi_test_rate_bound_evals() - e0;
        assert_int_equal(e, HP_OK);
        for (int k = 0; k < L.n; ++k) {
            double rate = L.bladders[k].rate_max, at;
            if (lof[k] & HP_BIND_RATE_DOWN) {
                assert_int_equal(hp_iab_ik(&L.bladders[k].iab, pb.ri_lo_si[k], &at), HP_OK);
                assert_true(fabs(at - P[k]) <= rate);
            }
            if (hif[k] & HP_BIND_RATE_UP) {
                assert_int_equal(hp_iab_ik(&L.bladders[k].iab, pb.ri_hi_si[k], &at), HP_OK);
                assert_true(fabs(at - P[k]) <= rate);
            }
        }
    }
    double per = (double)evals / (double)solves;
    print_message("ends after a jump: %lu solved, %.2f pressure evaluations each\n", solves, per);
    assert_true(solves > 20000);
    assert_true(per <= 3.1); /* measured 2.90; 3.61 from the cubic interpolant */
}

/* The cubic Hermite interpolant of ri(P) through the knots j, j + 1 of bladder k and their
 * slopes alone, at pw [Pa]: the start the quintic one replaced, the reference it is
 * measured against. */
static double cubic_guess(const hp_static_bounds *sb, int k, int j, double pw)
{
    const double *kp = sb->knot_p[k];
    double h = kp[j + 1] - kp[j], t = (pw - kp[j]) / h, sc = sb->iab_s[k].scale;
    double m0 = h / (sb->knot_d[k][j] * sc), m1 = h / (sb->knot_d[k][j + 1] * sc);
    double t2 = t * t, t3 = t2 * t;
    return (2.0 * t3 - 3.0 * t2 + 1.0) * sb->knot_ri[k][j] + (t3 - 2.0 * t2 + t) * m0 +
           (3.0 * t2 - 2.0 * t3) * sb->knot_ri[k][j + 1] + (t3 - t2) * m1;
}

/* 3. The root finds' start against the FK root, evenly over each bladder's knot range: the
 * largest relative distance of the quintic start and of the cubic reference. A start is no
 * answer (the root find brackets and iterates from any), so the bound is what the count of
 * evaluations above rests on: one Newton step from within 1e-9 (the iteration's error
 * squares: ~1e-18 of the radius) leaves the root to rounding. Measured on the default
 * layout: 1.9e-10 against 9.2e-8 (20 000 pressures a bladder). */
static void test_knot_guess_near_root(void **state)
{
    (void)state;
    hp_layout L;
    static hp_static_bounds sb;
    fixture(&L, &sb, NAN);
    const int n = HP_TEST_SMALL(20000, 1000);
    double worst_q = 0.0, worst_c = 0.0;
    for (int k = 0; k < L.n; ++k) {
        assert_true(sb.knots_ok[k]);
        const double *kp = sb.knot_p[k];
        int j = 0;
        for (int i = 0; i < n; ++i) {
            double pw = kp[0] + (kp[HP_RATE_KNOTS - 1] - kp[0]) * (i + 0.5) / n, r;
            while (j < HP_RATE_KNOTS - 2 && kp[j + 1] < pw) ++j;
            assert_int_equal(hp_iab_fk_limit(&L.bladders[k].iab, &sb.limit[k], pw, &r), HP_OK);
            double q = hpi_setup_knot_guess(&sb, k, pw), c = cubic_guess(&sb, k, j, pw);
            assert_true(isfinite(q));
            worst_q = fmax(worst_q, fabs(q - r) / r);
            worst_c = fmax(worst_c, fabs(c - r) / r);
        }
    }
    print_message("knot starts: quintic within %.2g of the root, cubic within %.2g\n", worst_q,
                  worst_c);
    assert_true(worst_q <= 1e-9);
    assert_true(100.0 * worst_q <= worst_c);
    /* Outside the knots: no start. */
    assert_true(isnan(hpi_setup_knot_guess(&sb, 0, nextafter(sb.knot_p[0][0], -INFINITY))));
    assert_true(
        isnan(hpi_setup_knot_guess(&sb, 0, nextafter(sb.knot_p[0][HP_RATE_KNOTS - 1], INFINITY))));
}

/* 4. hpi_setup_rate_surely_out never calls a radius outside its window when it is not: 500 Pa
 *    windows around uniform previous pressures with every end a stand-in, one bladder's
 *    radius drawn over three window widths around its exact window (the eager bounds) and
 *    at the knots' radii, the others at their windows' middles. Whenever it answers 1, that
 *    radius lies beyond an exact bound by more than the margin; and it does answer 1 for
 *    most radii beyond the knots that bracket the window (counted), so the test fires. */
static void test_surely_out_is_sure(void **state)
{
    (void)state;
    hp_layout L;
    static hp_static_bounds sb;
    fixture(&L, &sb, 500.0);
    uint64_t seed = 0x5e7e;
    const double margin = 2.0 * HP_BINDING_TOL_MM;
    long out = 0, far = 0, left_out = 0;
    for (int t = 0; t < 2000; ++t) {
        double P[HP_MAX_BLADDERS], rho[HP_MAX_BLADDERS];
        for (int k = 0; k < L.n; ++k) P[k] = uniform_p(&sb, k, &seed);
        hp_rate_memo mz, me;
        memset(&mz, 0, sizeof mz);
        memset(&me, 0, sizeof me);
        hp_problem pz, pe;
        unsigned lz[HP_MAX_BLADDERS], hz[HP_MAX_BLADDERS], le[HP_MAX_BLADDERS], he[HP_MAX_BLADDERS];
        memcpy(pz.p_prev, P, sizeof pz.p_prev);
        hpi_setup_rate_windows(&L, &pz);
        hp_rate_lazy z = {
            .L = &L, .b = &sb, .memo = &mz, .pb = &pz, .lo_flags = lz, .hi_flags = hz};
        assert_int_equal(hpi_setup_cycle_bounds_lazy(&z, NULL), HP_OK);
        assert_int_equal(hpi_setup_cycle_bounds_memo(&L, &sb, P, 1, &me, &pe, le, he, NULL), HP_OK);
        for (int k = 0; k < L.n; ++k) rho[k] = 0.5 * (pe.ro_lo[k] + pe.ro_hi[k]);
        assert_false(hpi_setup_rate_surely_out(&z, rho, L.n, margin));
        unsigned near;
        assert_false(hpi_setup_rate_surely_left(&L, &sb, P, rho, margin, &near));
        int k = (int)(test_rng_next(&seed) % (uint64_t)L.n);
        double w = pe.ro_hi[k] - pe.ro_lo[k], mid = rho[k];
        for (int i = 0; i < HP_RATE_KNOTS + 7; ++i) {
            rho[k] = i < HP_RATE_KNOTS
                         ? sb.knot_ro[k][i] * HP_MM_PER_M
                         : pe.ro_lo[k] - w + 3.0 * w * 0.5 * (lf_uniform(&seed) + 1.0);
            int said = hpi_setup_rate_surely_out(&z, rho, L.n, margin);
            if (said) assert_true(rho[k] < pe.ro_lo[k] - margin || rho[k] > pe.ro_hi[k] + margin);
            out += said;
            /* the same bracket before any bound is set (plan.c's direct answer) */
            int left = hpi_setup_rate_surely_left(&L, &sb, P, rho, margin, &near);
            if (left) assert_true(rho[k] < pe.ro_lo[k] - margin || rho[k] > pe.ro_hi[k] + margin);
            /* outside a window end (not the static bounds, which the direct chain's radii
             * meet), not for certain: near that end */
            if (!left && rho[k] >= sb.ro_lo[k] * HP_MM_PER_M &&
                rho[k] <= sb.ro_hi[k] * HP_MM_PER_M &&
                (rho[k] < pe.ro_lo[k] || rho[k] > pe.ro_hi[k]))
                assert_true(near & (1u << k));
            left_out += left;
            far += rho[k] < pe.ro_lo[k] - w || rho[k] > pe.ro_hi[k] + w;
        }
        rho[k] = mid;
    }
    print_message("%ld radii called outside their window for certain (%ld before any bound "
                  "is set), %ld drawn beyond a window width outside it\n",
                  out, left_out, far);
    assert_true(out > far / 2);
    assert_true(left_out > far / 2);
}

/* 5.: along a seeded chain of previous pressures (draw_pressure, one memo kept along it),
 * the lazy set-up, the knots' bracket of random radii, and the resolves one end at a time
 * (the lower first, then the upper, as a plan touches them) read the windows the caller
 * worked out (hpi_setup_rate_windows into hp_problem.w_lo, w_hi) and work out none of their
 * own: p_prev is overwritten with NaN once the windows are out (a window worked out from it
 * again would be NaN, and its bounds not the eager ones), no further hpi_setup_rate_windows
 * runs, and the ends resolved equal the eager bounds of an equal memo bit for bit. Counted
 * when each step worked its windows out itself: 4.6 a bladder (the set-up's and its
 * bounds', again in every resolve and every look of the bracket). */
static void test_windows_worked_out_once(void **state)
{
    (void)state;
    hp_layout L;
    static hp_static_bounds sb;
    fixture(&L, &sb, 500.0);
    hp_rate_memo mz, me;
    memset(&mz, 0, sizeof mz);
    memset(&me, 0, sizeof me);
    uint64_t seed = 0x0cea;
    unsigned long windows = 0, draws = 0;
    for (int t = 0; t < 500; ++t) {
        double P[HP_MAX_BLADDERS], rho[HP_MAX_BLADDERS];
        for (int k = 0; k < L.n; ++k) P[k] = draw_pressure(&sb, k, &seed);
        hp_problem pz, pe;
        unsigned lz[HP_MAX_BLADDERS], hz[HP_MAX_BLADDERS], le[HP_MAX_BLADDERS], he[HP_MAX_BLADDERS];
        memcpy(pz.p_prev, P, sizeof pz.p_prev);
        hpi_setup_rate_windows(&L, &pz);
        for (int k = 0; k < L.n; ++k) pz.p_prev[k] = NAN;
        unsigned long w0 = hpi_test_rate_windows();
        hp_rate_lazy z = {
            .L = &L, .b = &sb, .memo = &mz, .pb = &pz, .lo_flags = lz, .hi_flags = hz};
        hp_error ez = hpi_setup_cycle_bounds_lazy(&z, NULL);
        hp_error ee = hpi_setup_cycle_bounds_memo(&L, &sb, P, 1, &me, &pe, le, he, NULL);
        assert_int_equal(ez, ee);
        if (ez != HP_OK) continue;
        for (int k = 0; k < L.n; ++k) {
            double u = 0.5 * (lf_uniform(&seed) + 1.0);
            rho[k] = pz.ro_lo[k] + u * (pz.ro_hi[k] - pz.ro_lo[k]) + 1e-3 * lf_uniform(&seed);
        }
        (void)hpi_setup_rate_surely_out(&z, rho, L.n, 2.0 * HP_BINDING_TOL_MM);
        for (int k = 0; k < L.n; ++k) {
            assert_true(hpi_setup_rate_resolve(&z, k, 1u));
            assert_true(hpi_setup_rate_resolve(&z, k, 2u));
        }
        windows += hpi_test_rate_windows() - w0;
        draws += (unsigned long)L.n;
        same_bounds(L.n, &pz, &pe, lz, le, hz, he);
    }
    print_message("%lu bladder set-ups from the caller's windows: %lu windows worked out again\n",
                  draws, windows);
    assert_true(draws > 3000);
    assert_int_equal(windows, 0);
}

/* The stand-ins a set-up keeps (hp_rate_stand) and takes again for later windows. Seeded
 * chains on the default layout (rate 500 Pa): each bladder's centre drawn at least 600 Pa
 * inside its static interval (both window ends bound, every end a stand-in at set-up),
 * then 39 steps of that centre plus uniform noise of +-3 Pa (the loop benchmark's
 * readings), 50 draws. Each step sets the bounds up lazily with the kept stand-ins and
 * eagerly (hpi_setup_cycle_bounds_memo, a memo of its own), and checks every stand-in: its
 * outer radius strictly inside the eager bound, its point's pressure beyond the window end
 * by the rate slack (what puts it strictly inside: problem_setup.h), and the bound it
 * gives the bladder's static one or that point's outer radius, bit for bit. Chain A then
 * resolves the ends as a plan does: those that radii on a stand-in (a third of the
 * bladders each side, the rest between) come near (hpi_setup_rate_touch, whose resolves
 * are counted), then the rest one end at a time, so that each resolve meets the
 * other end's kept stand-in (exact_end's width test reads it); the bounds then equal the
 * eager ones bit for bit: what a plan decides does not depend on which stand-in it had.
 * Chain B resolves nothing and counts the stand-ins made anew on the noise steps. A kept
 * one stops serving when the noise moves its end past it, or when a crossing of a knot
 * back and forth leaves the kept knot more than a knot spacing inside: about the share of
 * ends within the noise's 6 Pa of a knot, 6/338 of a spacing, a third of the time (0.6 %;
 * measured 0.72 %). At most 5 % may be made anew; without the keeping every one would be
 * (100 %). */
static void test_kept_stand_ins_serve(void **state)
{
    (void)state;
    hp_layout L;
    static hp_static_bounds sb;
    fixture(&L, &sb, 500.0);
    for (int chain = 0; chain < 2; ++chain) {
        hp_rate_memo mz, me;
        hp_rate_stand st;
        memset(&mz, 0, sizeof mz);
        memset(&me, 0, sizeof me);
        memset(&st, 0, sizeof st);
        uint64_t seed = 0x57a0 + (uint64_t)chain;
        double P0[HP_MAX_BLADDERS];
        unsigned long noise_ends = 0, noise_new = 0, marked = 0, touched = 0;
        for (int t = 0; t < 50 * 40; ++t) {
            if (t % 40 == 0)
                for (int k = 0; k < L.n; ++k) {
                    double u = 0.5 * (lf_uniform(&seed) + 1.0);
                    P0[k] = sb.p_lo[k] + 600.0 + u * (sb.p_hi[k] - sb.p_lo[k] - 1200.0);
                }
            double P[HP_MAX_BLADDERS];
            for (int k = 0; k < L.n; ++k) P[k] = P0[k] + 3.0 * lf_uniform(&seed);
            hp_problem pz, pe;
            unsigned lz[HP_MAX_BLADDERS], hz[HP_MAX_BLADDERS], le[HP_MAX_BLADDERS],
                he[HP_MAX_BLADDERS];
            hp_rate_lazy z;
            unsigned long n0 = hpi_test_rate_stands_new(); /* the eager set-up makes none */
            both_setups(&L, &sb, P, &mz, &st, &me, &z, &pz, lz, hz, &pe, le, he);
            unsigned long made = hpi_test_rate_stands_new() - n0;
            for (int k = 0; k < L.n; ++k) {
                double sl = sb.rate_slack[k];
                if (z.lo[k]) {
                    assert_true(pz.ro_lo[k] > pe.ro_lo[k]);
                    assert_true(st.ok[0][k] && st.p[0][k] >= pz.w_lo[k] + sl);
                    double want = (st.ro[0][k] > sb.ro_lo[k] ? st.ro[0][k] : sb.ro_lo[k]) *
                                  HP_MM_PER_M;
                    assert_true(memcmp(&pz.ro_lo[k], &want, sizeof want) == 0);
                    ++marked;
                }
                if (z.hi[k]) {
                    assert_true(pz.ro_hi[k] < pe.ro_hi[k]);
                    assert_true(st.ok[1][k] && st.p[1][k] <= pz.w_hi[k] - sl);
                    double want = (st.ro[1][k] < sb.ro_hi[k] ? st.ro[1][k] : sb.ro_hi[k]) *
                                  HP_MM_PER_M;
                    assert_true(memcmp(&pz.ro_hi[k], &want, sizeof want) == 0);
                    ++marked;
                }
            }
            if (t % 40 != 0) {
                noise_ends += 2u * (unsigned long)L.n;
                noise_new += made;
            }
            if (chain == 1) continue;
            double rho[HP_MAX_BLADDERS];
            for (int k = 0; k < L.n; ++k) { /* on the lower stand-in, the upper, or between */
                int at = (int)(test_rng_next(&seed) % 3);
                double u = at == 0 ? 0.0 : at == 1 ? 1.0 : 0.5 * (lf_uniform(&seed) + 1.0);
                rho[k] = pz.ro_lo[k] + u * (pz.ro_hi[k] - pz.ro_lo[k]);
            }
            unsigned long r0 = hpi_test_rate_resolves();
            assert_true(hpi_setup_rate_touch(&z, rho, L.n, 2.0 * HP_BINDING_TOL_MM));
            touched += hpi_test_rate_resolves() - r0;
            for (int k = 0; k < L.n; ++k) {
                assert_true(hpi_setup_rate_resolve(&z, k, 1u));
                assert_true(hpi_setup_rate_resolve(&z, k, 2u));
            }
            same_bounds(L.n, &pz, &pe, lz, le, hz, he);
        }
        print_message("chain %c: %lu stand-ins checked; on the noise steps %lu of %lu ends made "
                      "anew (%.2f %%); %lu ends resolved by radii on them\n",
                      chain ? 'B' : 'A', marked, noise_new, noise_ends,
                      100.0 * (double)noise_new / (double)noise_ends, touched);
        assert_int_equal(marked, 50u * 40u * 2u * (unsigned long)L.n);
        if (chain == 0) assert_true(touched > 0);
        if (chain == 1) assert_true(noise_new * 20u <= noise_ends);
    }
}

/* A bladder whose rate window reaches past a static pressure limit: the window end beyond
 * it leaves the static bound, the other end is a stand-in. Seeded draws on the default
 * layout (rate 500 Pa), every bladder's previous pressure within 0.9 of the rate of one of
 * its limits, or on it (its own draw of the side), 2 000 set-ups with an empty stand-in
 * keep (hp_rate_stand), half of them from an empty memo and half from the memo of windows
 * elsewhere. Each bladder's far end is a stand-in that the set-up keeps (st.ok, the outer
 * radius its bound, bit for bit: the short way, lazy_static_end; the general way made one
 * without keeping it), strictly inside the eager bound
 * (hpi_setup_cycle_bounds_memo, a memo of its own), with the rate flag where it binds; the
 * near end is the eager bound and flag bit for bit; every end resolved then gives the
 * eager bounds bit for bit. The set-up makes one stand-in a bladder (hpi_test_rate_stands_new:
 * the general way's are not counted). Not reached here: a far end without a stand-in (the
 * short way's -1) and a window too narrow for one, which take the general way. */
static void test_static_end_stand_ins(void **state)
{
    (void)state;
    hp_layout L;
    static hp_static_bounds sb;
    fixture(&L, &sb, 500.0);
    uint64_t seed = 0x5eed5;
    unsigned long binds = 0;
    for (int t = 0; t < 2000; ++t) {
        double P[HP_MAX_BLADDERS];
        int low[HP_MAX_BLADDERS];
        for (int k = 0; k < L.n; ++k) {
            low[k] = (int)(test_rng_next(&seed) % 2);
            double u = 0.5 * (lf_uniform(&seed) + 1.0) * (t % 5 ? 0.9 : 0.0);
            P[k] = low[k] ? sb.p_lo[k] + u * 500.0 : sb.p_hi[k] - u * 500.0;
        }
        hp_rate_memo mz, me;
        memset(&mz, 0, sizeof mz);
        hp_problem pz, pe;
        unsigned lz[HP_MAX_BLADDERS], hz[HP_MAX_BLADDERS], le[HP_MAX_BLADDERS], he[HP_MAX_BLADDERS];
        if (t % 2) memo_elsewhere(&L, &sb, &seed, &mz, &pe, le, he);
        me = mz;
        hp_rate_stand st;
        memset(&st, 0, sizeof st);
        hp_rate_lazy z;
        unsigned long n0 = hpi_test_rate_stands_new(); /* the eager set-up makes none */
        both_setups(&L, &sb, P, &mz, &st, &me, &z, &pz, lz, hz, &pe, le, he);
        /* one stand-in made (and kept) a bladder: none took the general way */
        assert_int_equal(hpi_test_rate_stands_new() - n0, (unsigned long)L.n);
        for (int k = 0; k < L.n; ++k) {
            int far = low[k]; /* the far end: the upper when near the lower limit */
            assert_true(far ? pz.w_lo[k] <= sb.p_lo[k] : pz.w_hi[k] >= sb.p_hi[k]);
            assert_int_equal(far ? z.hi[k] : z.lo[k], 1);
            assert_int_equal(far ? z.lo[k] : z.hi[k], 0);
            assert_true(st.ok[far][k]);
            if (far) {
                double want = (st.ro[1][k] < sb.ro_hi[k] ? st.ro[1][k] : sb.ro_hi[k]) * HP_MM_PER_M;
                assert_true(memcmp(&pz.ro_hi[k], &want, sizeof want) == 0);
                assert_true(pz.ro_hi[k] < pe.ro_hi[k]);
                assert_int_equal(hz[k], want != sb.ro_hi[k] * HP_MM_PER_M ? HP_BIND_RATE_UP
                                                                          : sb.hi_flags[k]);
                assert_true(memcmp(&pz.ro_lo[k], &pe.ro_lo[k], sizeof(double)) == 0);
                assert_true(memcmp(&pz.ri_lo_si[k], &pe.ri_lo_si[k], sizeof(double)) == 0);
                assert_int_equal(lz[k], le[k]);
            } else {
                double want = (st.ro[0][k] > sb.ro_lo[k] ? st.ro[0][k] : sb.ro_lo[k]) * HP_MM_PER_M;
                assert_true(memcmp(&pz.ro_lo[k], &want, sizeof want) == 0);
                assert_true(pz.ro_lo[k] > pe.ro_lo[k]);
                assert_int_equal(lz[k], want != sb.ro_lo[k] * HP_MM_PER_M ? HP_BIND_RATE_DOWN
                                                                          : sb.lo_flags[k]);
                assert_true(memcmp(&pz.ro_hi[k], &pe.ro_hi[k], sizeof(double)) == 0);
                assert_true(memcmp(&pz.ri_hi_si[k], &pe.ri_hi_si[k], sizeof(double)) == 0);
                assert_int_equal(hz[k], he[k]);
            }
            binds += (far ? hz[k] : lz[k]) == (far ? HP_BIND_RATE_UP : HP_BIND_RATE_DOWN);
        }
        for (int k = 0; k < L.n; ++k) assert_true(hpi_setup_rate_resolve(&z, k, 3u));
        same_bounds(L.n, &pz, &pe, lz, le, hz, he);
    }
    print_message("%lu of %lu bladders at a static limit: the far end's stand-in binds\n", binds,
                  2000u * (unsigned long)L.n);
    /* every far window end lies inside the static range (within 1.9 rates of the near
     * limit), so every far stand-in binds */
    assert_int_equal(binds, 2000u * (unsigned long)L.n);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_loop_windows_have_stand_ins),
        cmocka_unit_test(test_fast_ends_equal_reference),
        cmocka_unit_test(test_far_end_starts_near),
        cmocka_unit_test(test_knot_guess_near_root),
        cmocka_unit_test(test_surely_out_is_sure),
        cmocka_unit_test(test_windows_worked_out_once),
        cmocka_unit_test(test_kept_stand_ins_serve),
        cmocka_unit_test(test_static_end_stand_ins),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
