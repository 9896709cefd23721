// The vortex-blob method (include/mollify/vortex): the periodic kernels
// against image sums and closed forms, the compact blob against the free
// Biot-Savart velocity of the Poisson solver and Anderson's closed-form mass
// fraction, the invariants and the order of RK4, bad input.
#include <mollify/kernel.hpp>
#include <mollify/poisson.hpp>
#include <mollify/vortex.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <string>
#include <vector>

namespace vortex = mollify::vortex;
using vortex::Velocity;

namespace {

constexpr double pi = std::numbers::pi;

template <class F>
void expect_error(F&& f, const std::string& needle) {
    try {
        f();
        ADD_FAILURE() << "no error; expected one naming '" << needle << "'";
    } catch (const mollify::Error& e) {
        EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
}

// The row of point vortices summed image by image: |n| <= K, plus the tail
// sum_{n > K} of the pair (n, -n), -y/pi resp. -x/pi times sum 1/n^2, whose
// neglected terms are O(K^-3) = 1e-15 at K = 1e5.
Velocity image_sum(double x, double y, bool with_centre) {
    constexpr long K = 100000;
    long double u = 0, v = 0;
    for (long n = K; n >= 1; --n)
        for (long s : {n, -n}) {
            const long double dx = x + s, r2 = dx * dx + (long double)y * y;
            u += -y / (2 * pi * r2);
            v += dx / (2 * pi * r2);
        }
    if (with_centre) {
        const Velocity c = vortex::point_vortex(x, y);
        u += c[0];
        v += c[1];
    }
    const long double tail = 1.0L / K - 1.0L / (2.0L * K * K);  // sum_{n > K} 1/n^2
    return {double(u - y / pi * tail), double(v - x / pi * tail)};
}

TEST(Vortex, PeriodicPointVortexIsTheImageSum) {
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> c(-0.5, 0.5);
    for (int i = 0; i < 20; ++i) {
        const double x = c(rng), y = c(rng) * (i % 2 ? 1.0 : 0.1);
        const Velocity a = vortex::periodic_point_vortex(x, y), b = image_sum(x, y, true);
        // Values O(1/r); 1e-13 relative: the tail's O(K^-3) and the long
        // sum's rounding (~K * 1e-19) are far below it.
        const double scale = std::hypot(b[0], b[1]);
        EXPECT_NEAR(a[0], b[0], 1e-13 * scale) << x << " " << y;
        EXPECT_NEAR(a[1], b[1], 1e-13 * scale) << x << " " << y;
        // Period 1 in x.
        const Velocity p = vortex::periodic_point_vortex(x + 3, y);
        EXPECT_NEAR(p[0], a[0], 1e-13 * scale);
        EXPECT_NEAR(p[1], a[1], 1e-13 * scale);
    }
}

// The images without the centre, near 0: the zeta series against the image
// sum (both regular), across the switch at |z| = 0.05 and down to |z| = 1e-300
// and 0, where the difference form would lose everything.
TEST(Vortex, ImagesOfTheRowAreRegularAtTheCentre) {
    for (double r : {0.3, 0.0501, 0.0499, 0.02, 1e-3, 1e-8, 1e-300, 0.0})
        for (double t : {0.1, 1.3, 2.9, 4.4}) {
            const double x = r * std::cos(t), y = r * std::sin(t);
            const Velocity a = vortex::periodic_point_vortex_images(x, y), b = image_sum(x, y, false);
            // |K - 1/(2 pi z)| ~ (pi/6)|z|: absolute 1e-15 (the difference form
            // rounds to eps/(2 pi |z|) <= 8e-16 at |z| >= 0.05; the series to
            // a few ulps).
            EXPECT_NEAR(a[0], b[0], 1e-15) << r << " " << t;
            EXPECT_NEAR(a[1], b[1], 1e-15) << r << " " << t;
        }
    const Velocity z = vortex::periodic_point_vortex_images(0, 0);
    EXPECT_EQ(z[0], 0.0);
    EXPECT_EQ(z[1], 0.0);
}

// Anderson's 2D mollifier c (1 - q^2)^M has mass fraction 1 - (1 - q^2)^(M+1)
// inside q = r/h (integrate 2 pi s c (1 - s^2)^M): the free blob's velocity
// in closed form, independent of the tables.
TEST(Vortex, CompactBlobIsTheMollifiedPointVortex) {
    const double h = 0.25;
    for (int M : {1, 4, 9}) {
        const vortex::CompactBlob blob(mollify::kernel("mollifier:M=" + std::to_string(M), 2), h);
        for (int i = 1; i <= 200; ++i) {
            const double q = i / 200.0, t = 0.37 * i, r = q * h;
            const double x = r * std::cos(t), y = r * std::sin(t);
            const Velocity images = vortex::periodic_point_vortex_images(x, y), b = blob(x, y);
            const double m = -std::expm1((M + 1) * std::log1p(-q * q));  // no cancellation at small q
            const Velocity exact = {-y * m / (2 * pi * r * r), x * m / (2 * pi * r * r)};
            // 1e-13 relative (450 ulps): the runtime's phi'/r is within
            // 133 intrinsic ulps (accuracy_test, mollifiers), the closed form
            // m here within a few.
            const double scale = std::hypot(exact[0], exact[1]);
            EXPECT_NEAR(b[0] - images[0], exact[0], 1e-13 * scale) << "M = " << M << ", q = " << q;
            EXPECT_NEAR(b[1] - images[1], exact[1], 1e-13 * scale) << "M = " << M << ", q = " << q;
        }
        // At the centre: no velocity; beyond the support: the point-vortex row.
        EXPECT_EQ(blob(0, 0)[0], 0.0);
        const Velocity out = blob(0.3, 0.1), row = vortex::periodic_point_vortex(0.3, 0.1);
        EXPECT_EQ(out[0], row[0]);
        EXPECT_EQ(out[1], row[1]);
    }
}

// The same free blob as the Poisson solver's 2D Biot-Savart velocity (one
// source of circulation 1 at the origin), for a Wendland kernel and a
// high-order combination.
TEST(Vortex, CompactBlobAgreesWithPoissonBiotSavart) {
    const double h = 0.2;
    for (const char* spec : {"wendland:k=2", "combo:m=3,base=wendland:k=2"}) {
        const mollify::Kernel k = mollify::kernel(spec, 2);
        const vortex::CompactBlob blob(k, h);
        std::vector<double> sx{0.0}, sy{0.0}, q{1.0}, d{h}, tx, ty;
        for (int i = 1; i <= 50; ++i) {
            tx.push_back(h * i / 51.0 * std::cos(i));
            ty.push_back(h * i / 51.0 * std::sin(i));
        }
        const auto f = mollify::poisson::direct<2>(k, {{sx, sy}, q, d}, {{tx, ty}});
        const auto u = mollify::poisson::biot_savart(f);
        for (std::size_t i = 0; i < tx.size(); ++i) {
            const Velocity images = vortex::periodic_point_vortex_images(tx[i], ty[i]), b = blob(tx[i], ty[i]);
            // The same runtime quantity phi'/r through two code paths: 4 ulps.
            const double scale = std::hypot(u[0][i], u[1][i]);
            EXPECT_NEAR(b[0] - images[0], u[0][i], 1e-15 * scale) << spec;
            EXPECT_NEAR(b[1] - images[1], u[1][i], 1e-15 * scale) << spec;
        }
    }
}

TEST(Vortex, AlgebraicBlobIsKrasnysKernel) {
    // Far from the blob it is the point-vortex row up to delta^2 / D.
    const vortex::AlgebraicBlob tiny(1e-9);
    const Velocity a = tiny(0.3, -0.2), p = vortex::periodic_point_vortex(0.3, -0.2);
    EXPECT_NEAR(a[0], p[0], 1e-15 * std::abs(p[0]));
    EXPECT_NEAR(a[1], p[1], 1e-15 * std::abs(p[1]));
    // Far above and below: the sheet's jump, -+1/2 (no overflow at |y| = 1e3).
    const vortex::AlgebraicBlob b(0.25);
    EXPECT_EQ(b(0.1, 1e3)[0], -0.5);
    EXPECT_EQ(b(0.1, -1e3)[0], 0.5);
    EXPECT_NEAR(b(0.1, 10)[0], -0.5, 1e-15);
    // Odd, and finite at its own centre.
    for (double x : {0.1, 0.49, 0.5, 0.0}) {
        const Velocity k = b(x, 0.07), m = b(-x, -0.07);
        EXPECT_EQ(k[0], -m[0]) << x;
        EXPECT_EQ(k[1], -m[1]) << x;
    }
    EXPECT_EQ(b(0, 0)[0], 0.0);
    EXPECT_EQ(b(0, 0)[1], 0.0);
    // Near 0 the free algebraic blob with delta_f = delta / (sqrt 2 pi), up
    // to the images (K - 1/(2 pi z) = O(z)) and O(r^2) terms of D.
    const double df = 0.25 / (std::sqrt(2.0) * pi), x = 0.01, y = 0.0;
    EXPECT_NEAR(b(x, y)[1], x / (2 * pi * (x * x + df * df)), 2e-3 * x / (2 * pi * (x * x + df * df)));
}

// The sheet keeps its circulation (exactly), its impulse sum Gamma y (the
// pair sum of an odd kernel: rounding only) and its point symmetry about
// (1/2, 0) (particle j and N - j).
template <class Blob>
void check_invariants(const Blob& blob) {
    const long n = 64;
    vortex::Sheet s = vortex::krasny_sheet(n, 0.01);
    const double c0 = vortex::circulation(s), p0 = vortex::impulse_y(s);
    vortex::advance(blob, s, 0.05, 20);
    EXPECT_EQ(vortex::circulation(s), c0);
    // |Gamma u| <= 1/N, 20 steps of 0.05, N^2 terms: 1e-15 absolute.
    EXPECT_NEAR(vortex::impulse_y(s), p0, 1e-15) << blob.name();
    for (long j = 1; j < n; ++j) {
        // Initial asymmetry of rounding a = j/N: 1 ulp; grows mildly: 1e-13.
        EXPECT_NEAR(s.x[j] + s.x[n - j], 1.0, 1e-13) << blob.name() << " j = " << j;
        EXPECT_NEAR(s.y[j] + s.y[n - j], 0.0, 1e-13) << blob.name() << " j = " << j;
    }
    // The sheet moved (the test would pass on a frozen sheet otherwise).
    EXPECT_GT(std::abs(s.y[n / 4] - vortex::krasny_sheet(n, 0.01).y[n / 4]), 1e-4) << blob.name();
}

TEST(Vortex, SheetKeepsItsInvariants) {
    check_invariants(vortex::AlgebraicBlob(0.25));
    check_invariants(vortex::CompactBlob(mollify::kernel("mollifier:M=4", 2), 0.25));
    // The treecode at order 30 (truncation ~1e-15 of the velocities), with
    // a support that leaves far cells (h = 0.1 of the period) but still damps
    // the short waves that would amplify rounding (Krasny 1986).
    check_invariants(vortex::SheetTreecode(vortex::CompactBlob(mollify::kernel("mollifier:M=4", 2), 0.1), 0.4, 30));
}

// A rolled, noisy sheet: x over seven periods, circulations of both signs,
// a few particles far above and below (|y| = 3 and 25, past the closed
// form's |y| > 20 switch), and 20 particles on one point (a cell of radius 0).
vortex::Sheet hard_sheet(long n, double spread) {
    vortex::Sheet s = vortex::krasny_sheet(n, 0.2);
    std::mt19937_64 rng(11);
    std::normal_distribution<double> noise(0, 1);
    for (long j = 0; j < n; ++j) {
        s.x[j] += spread * noise(rng) + static_cast<double>(j % 7 - 3);
        s.y[j] += spread * noise(rng);
        s.gamma[j] *= 1 + 0.8 * noise(rng);
    }
    for (long j : {1L, 2L, 3L}) s.y[j] = j == 1 ? 3.0 : j == 2 ? -25.0 : 25.0;
    for (long j = 10; j < 30; ++j) {
        s.x[j] = 0.3;
        s.y[j] = 0.1;
    }
    return s;
}

double max_difference(const std::vector<double>& u, const std::vector<double>& v, const std::vector<double>& u2,
                      const std::vector<double>& v2) {
    double e = 0;
    for (std::size_t j = 0; j < u.size(); ++j) e = std::max(e, std::hypot(u[j] - u2[j], v[j] - v2[j]));
    return e;
}

// The treecode against the direct sum, particle by particle. A priori
// (sheet_treecode.hpp) each accepted cell C errs by about
// |Gamma|_C / (2 pi d) theta^(p+1) / (1 - theta) with d >= h, so the sum by
// at most E = theta^(p+1) / (1 - theta) sum |Gamma| / (2 pi h); the error
// must stay below E and fall with p, to rounding at p = 30: each of the
// sums' terms is at most |Gamma| (1 / (2 pi h) + 1) (the blob's velocity is
// largest at its edge; the images add at most ~1), each rounded to a few
// eps, so 64 eps sum |Gamma| (1 / (2 pi h) + 1).
// Three sheets: the noisy one at two supports (the opening ratio decides),
// and a dense strip (0.1 x 0.01, leaves ~1e-3 across) at h = 0.01, where
// the support decides which cells are far: a blob within h of a far cell
// would differ from the point vortex by up to its whole velocity.
vortex::Sheet dense_strip(long n) {
    vortex::Sheet s = vortex::krasny_sheet(n, 0.0);
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> c(0, 1);
    for (long j = 0; j < n; ++j) {
        s.x[j] = 0.3 + 0.1 * c(rng);
        s.y[j] = 0.01 * c(rng);
        s.gamma[j] *= c(rng) - 0.3;
    }
    return s;
}

TEST(Vortex, TreecodeIsTheDirectSum) {
    const long n = 1000;
    for (double h : {0.02, 0.002, 0.01}) {
        const vortex::Sheet s = h == 0.01 ? dense_strip(n) : hard_sheet(n, 0.05);
        const vortex::CompactBlob blob(mollify::kernel("wendland:k=2", 2), h);
        std::vector<double> u, v, ut, vt;
        vortex::velocity(blob, s, u, v);
        double total = 0, fastest = 0;
        for (std::size_t j = 0; j < s.size(); ++j) {
            total += std::abs(s.gamma[j]);
            fastest = std::max(fastest, std::hypot(u[j], v[j]));
        }
        const double theta = 0.4, rounding = 64 * 0x1p-52 * total * (1 / (2 * pi * h) + 1);
        double previous = INFINITY;
        for (int p : {4, 8, 16, 30}) {
            vortex::velocity(vortex::SheetTreecode(blob, theta, p), s, ut, vt);
            const double e = max_difference(u, v, ut, vt), bound = std::pow(theta, p + 1) / (1 - theta) * total / (2 * pi * h);
            EXPECT_LE(e, std::max(bound, rounding)) << "h = " << h << ", p = " << p;
            EXPECT_LT(e, previous / 20) << "h = " << h << ", p = " << p << ": no convergence";
            previous = std::max(e, rounding);
        }
        EXPECT_LE(previous, rounding) << "h = " << h;
        // The treecode needs the far field: at this h most pairs are far.
        EXPECT_GT(fastest, 0.1);
    }
}

// Tiny supports and clusters (h = 1e-9, particles 1e-10 .. 1e-6 apart, a
// cell of radius 0): the expansion is scaled by rho and d, so nothing over-
// or underflows; and a single particle moves not at all.
TEST(Vortex, TreecodeAtTinySupports) {
    const double h = 1e-9;
    vortex::Sheet s = hard_sheet(600, 1e-7);
    for (long j = 100; j < 300; ++j) {
        s.x[j] = 0.5 + 1e-10 * static_cast<double>(j);
        s.y[j] = 1e-10 * std::sin(static_cast<double>(j));
    }
    // x in [0, 1) as the tree holds it: differences of x across periods
    // (ulp 4e-16 at |x| ~ 3) would move velocities of pairs 1e-7 apart by
    // 4e-9 relative in the direct sum itself.
    for (double& x : s.x) x -= std::floor(x);
    const vortex::CompactBlob blob(mollify::kernel("combo:m=3,base=wendland:k=2", 2), h);
    std::vector<double> u, v, ut, vt;
    vortex::velocity(blob, s, u, v);
    vortex::velocity(vortex::SheetTreecode(blob, 0.4, 30), s, ut, vt);
    double fastest = 0;
    for (std::size_t j = 0; j < s.size(); ++j) {
        ASSERT_TRUE(std::isfinite(ut[j]) && std::isfinite(vt[j])) << j;
        fastest = std::max(fastest, std::hypot(u[j], v[j]));
    }
    // Velocities up to ~1/(2 pi 1e-10): rounding of sums of 600 terms, 1e-13.
    EXPECT_LE(max_difference(u, v, ut, vt), 1e-13 * fastest);
    EXPECT_GT(fastest, 1e6);
    vortex::Sheet one = vortex::krasny_sheet(1, 0.0);
    vortex::velocity(vortex::SheetTreecode(blob, 0.4, 10), one, ut, vt);
    EXPECT_EQ(ut[0], 0.0);
    EXPECT_EQ(vt[0], 0.0);
}

// Classical RK4 is fourth order: the error against a fine step drops ~16x
// per halving (asserted in [13, 19]; higher terms and the reference's own
// error move it by a few per cent at these steps).
TEST(Vortex, RungeKuttaIsFourthOrder) {
    const vortex::AlgebraicBlob blob(0.25);
    auto run = [&](double dt) {
        vortex::Sheet s = vortex::krasny_sheet(32, 0.05);
        vortex::advance(blob, s, dt, std::lround(1.0 / dt));
        return s;
    };
    const vortex::Sheet ref = run(1.0 / 320);
    auto error = [&](double dt) {
        const vortex::Sheet s = run(dt);
        double e = 0;
        for (std::size_t j = 0; j < s.size(); ++j) e = std::max({e, std::abs(s.x[j] - ref.x[j]), std::abs(s.y[j] - ref.y[j])});
        return e;
    };
    const double e1 = error(0.1), e2 = error(0.05), e3 = error(0.025);
    EXPECT_GT(e1 / e2, 13) << e1 << " " << e2;
    EXPECT_LT(e1 / e2, 19) << e1 << " " << e2;
    EXPECT_GT(e2 / e3, 13) << e2 << " " << e3;
    EXPECT_LT(e2 / e3, 19) << e2 << " " << e3;
}

TEST(Vortex, BadInputNamesTheValue) {
    expect_error([] { vortex::AlgebraicBlob(0.0); }, "delta = 0");
    expect_error([] { vortex::AlgebraicBlob(-0.25); }, "delta = -0.25");
    expect_error([] { vortex::AlgebraicBlob(std::nan("")); }, "delta = nan");
    const auto k = mollify::kernel("wendland:k=2", 2);
    expect_error([&] { vortex::CompactBlob(k, 0.75); }, "h = 0.75");
    expect_error([&] { vortex::CompactBlob(k, -1); }, "h = -1");
    expect_error([] { vortex::CompactBlob(mollify::kernel("wendland:k=2", 3), 0.25); }, "is not a 2D kernel");
    expect_error([] { vortex::krasny_sheet(0, 0.01); }, "N = 0");
    const vortex::CompactBlob blob(k, 0.25);
    expect_error([&] { vortex::SheetTreecode(blob, 1.0, 10); }, "theta = 1 is not in (0, 1)");
    expect_error([&] { vortex::SheetTreecode(blob, std::nan(""), 10); }, "theta = nan");
    expect_error([&] { vortex::SheetTreecode(blob, 0.5, 0); }, "order p = 0 is outside 1..40");
    expect_error([&] { vortex::SheetTreecode(blob, 0.5, 41); }, "order p = 41");
    vortex::Sheet bad = vortex::krasny_sheet(100, 0.01);
    bad.x[42] = INFINITY;
    std::vector<double> u, v;
    expect_error([&] { vortex::velocity(vortex::SheetTreecode(blob, 0.5, 10), bad, u, v); }, "particle 42");
    const vortex::AlgebraicBlob b(0.25);
    vortex::Sheet s = vortex::krasny_sheet(8, 0.01);
    expect_error([&] { vortex::advance(b, s, 0.0, 1); }, "dt = 0");
    s.y[3] = std::nan("");
    expect_error([&] { vortex::advance(b, s, 0.1, 1); }, "particle 3");
    vortex::Sheet e;
    expect_error([&] { vortex::advance(b, e, 0.1, 1); }, "no particles");
}

}  // namespace
