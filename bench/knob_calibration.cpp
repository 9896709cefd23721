// knob_calibration: the measurements behind the 3D accuracy knob's constants
// (include/mollify/poisson/tolerance.hpp, detail::calibration,
// detail::lowest_order(3) and detail::cost_model): the treecode's relative L2
// field error and one-thread CPU time over a grid of (theta, p), four sets:
//   - treecode_bench's neutral set, N = 10^5 uniform in [0, 1)^3
//     (bench/charge_sets.hpp), mollifier:M=4 with delta = 2 N^(-1/3),
//     errors at the first 1000 points against direct summation (neutral
//     charges: the far field cancels, so relative errors are 5-40x those of
//     positive charges at high orders);
//   - the knob test's Gaussian blob (tests/poisson_free_test.cpp, AccuracyKnob:
//     5000 sources, wendland:k=3, delta = 0.05), neutral, errors at every source;
//   - treecode_bench's positive set (the same points, charges in [0, 1]);
//   - a Plummer sphere of 2*10^4 equal masses, wendland:k=3, delta = 0.05,
//     errors at the first 2000 (centrally concentrated and one-signed: at
//     low orders above the neutral sets' model).
// Then the error model C (alpha r(theta))^(p+1), r = theta/(2 - theta) (the
// full M2L's truncation ratio for a balanced pair at the opening angle,
// multipole.hpp), as the tightest envelope of the measurements at the orders
// the knob chooses: for each
// alpha, C is the largest measured error/(alpha r)^(p+1) (so the model is
// never below a measurement), and alpha minimises the summed log of
// model/measured; and the uniform set's times fitted to
// n(theta) + b (p + 1)^k theta^-j: the near field's time per opening angle
// (it grows in steps as leaf pairs fail the test, which no power of theta
// follows: theta^-3 was 22 % off), the far field's as a power law, by least
// squares of the relative deviation (Eigen), (k, j) in {3..6} x {1..4} the
// one with the smallest largest deviation, for the cost model's table and
// constants. Writes a Markdown table with the load before and after:
//
//   cmake --build build --target bench-knob    (about 8 minutes; OMP_NUM_THREADS=1)
#include <mollify/kernel.hpp>
#include <mollify/poisson.hpp>
#include <mollify/tables/mollifier/M_4_D3.hpp>

#include "charge_sets.hpp"
#include "cpu_time.hpp"
#include "load_average.hpp"

// A 45 x 6 least-squares problem: Eigen's AVX-512 paths buy nothing here
// and trip GCC 12's -Wmaybe-uninitialized inside its intrinsics at -O3.
#define EIGEN_DONT_VECTORIZE
#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <numbers>
#include <random>
#include <string>
#include <string_view>
#include <vector>

namespace poisson = mollify::poisson;
namespace bench = mollify::bench;

namespace {

struct Point {
    std::string set;
    bool one_signed;  // every charge of one sign (such sets are also fitted alone)
    double theta;
    int p;
    double cpu_s, e_l2, phi_l2;
};

// E (x0 y0 z0 x1 ...) and phi of the first m points.
std::pair<std::vector<double>, std::vector<double>> first(const poisson::Field<3>& f, std::size_t m) {
    std::vector<double> e(3 * m), phi(m);
    for (std::size_t i = 0; i < m; ++i) {
        phi[i] = f.potential[i];
        for (std::size_t c = 0; c < 3; ++c) e[3 * i + c] = f.field[c][i];
    }
    return {e, phi};
}

template <class K>
void sweep(const std::string& name, bool one_signed, const K& kernel, const poisson::Sources<3>& s, std::size_t m,
           const std::vector<double>& thetas, const std::vector<int>& orders, std::vector<Point>& out) {
    const mollify::Points<3> targets{std::span<const double>(s.x[0].data(), m), std::span<const double>(s.x[1].data(), m),
                                     std::span<const double>(s.x[2].data(), m)};
    const auto [e_ref, phi_ref] = first(poisson::direct<3>(kernel, s, targets), m);
    for (const double theta : thetas)
        for (const int p : orders) {
            const double t0 = bench::cpu_seconds();
            const auto f = poisson::Treecode<3, K>(kernel, s, {.theta = theta, .order = p}).evaluate();
            const double cpu = bench::cpu_seconds() - t0;
            const auto [e, phi] = first(f, m);
            out.push_back({name, one_signed, theta, p, cpu, poisson::relative_l2(e, e_ref), poisson::relative_l2(phi, phi_ref)});
            std::printf("%s theta %.2f p %2d: %.3f CPU s, E %.3g, phi %.3g\n", name.c_str(), theta, p, cpu,
                        out.back().e_l2, out.back().phi_l2);
            std::fflush(stdout);
        }
}

}  // namespace

int main(int argc, char** argv) {
    std::string md;
    for (int i = 1; i < argc; ++i)
        if (std::string_view(argv[i]).substr(0, 5) == "--md=") md = argv[i] + 5;
    const std::string before = bench::load_average();
    std::vector<Point> points;

    const bench::ChargeSet u = bench::charge_set(100000, bench::Charges::neutral);
    const std::vector<double> du{2 / std::cbrt(1e5)};
    const poisson::Sources<3> su{{u.x[0], u.x[1], u.x[2]}, u.q, du};
    using Fast = mollify::StaticKernel<mollify::tables::mollifier_M_4_D3, mollify::Precision::fast>;
    sweep("uniform 1e5", false, Fast{}, su, 1000, {0.3, 0.4, 0.5, 0.6, 0.7, 0.8}, {4, 6, 8, 10, 12, 14, 16, 18, 20}, points);

    std::mt19937_64 rng(31);  // the knob test's blob
    std::normal_distribution<double> g(0, 1);
    std::uniform_real_distribution<double> q(-0.5, 0.5);
    std::array<std::vector<double>, 3> bx;
    std::vector<double> bq;
    for (int j = 0; j < 5000; ++j) {
        for (int c = 0; c < 3; ++c) bx[static_cast<std::size_t>(c)].push_back(g(rng));
        bq.push_back(q(rng));
    }
    const std::vector<double> db{0.05};
    const poisson::Sources<3> sb{{bx[0], bx[1], bx[2]}, bq, db};
    sweep("blob 5000", false, mollify::kernel("wendland:k=3", 3), sb, 5000, {0.3, 0.4, 0.5, 0.6, 0.7, 0.8},
          {2, 4, 6, 8, 10, 12, 14, 16, 18, 20}, points);

    // One-signed charges: treecode_bench's positive set, and a Plummer
    // sphere of equal masses (a star cluster's centrally concentrated,
    // gravity-like distribution, cut at 10 scale radii), which below the
    // knob's lowest order measured above the model (tolerance.hpp).
    const bench::ChargeSet up = bench::charge_set(100000, bench::Charges::positive);
    const poisson::Sources<3> sup{{up.x[0], up.x[1], up.x[2]}, up.q, du};
    sweep("uniform 1e5 positive", true, Fast{}, sup, 1000, {0.3, 0.4, 0.5, 0.6, 0.7, 0.8},
          {4, 6, 8, 10, 12, 14, 16, 18, 20}, points);
    std::mt19937_64 prng(47);
    const auto unit = [&] { return (static_cast<double>(prng() >> 11) + 0.5) * 0x1p-53; };  // in (0, 1)
    std::array<std::vector<double>, 3> px;
    while (px[0].size() < 20000) {
        // the enclosed mass M(r) = r^3 / (1 + r^2)^(3/2) inverted at a uniform draw
        const double r = 1 / std::sqrt(std::pow(unit(), -2.0 / 3) - 1);
        const double z = 2 * unit() - 1, phi = 2 * std::numbers::pi * unit(), s = std::sqrt(1 - z * z);
        if (r > 10) continue;
        px[0].push_back(r * s * std::cos(phi));
        px[1].push_back(r * s * std::sin(phi));
        px[2].push_back(r * z);
    }
    const std::vector<double> pq(px[0].size(), 1.0), dp{0.05};
    const poisson::Sources<3> sp{{px[0], px[1], px[2]}, pq, dp};
    sweep("Plummer 2e4 equal masses", true, mollify::kernel("wendland:k=3", 3), sp, 2000,
          {0.3, 0.4, 0.5, 0.6, 0.7, 0.8}, {2, 4, 6, 8, 10, 12, 14, 16, 18, 20}, points);
    const std::string after = bench::load_average();

    // Error envelope over the points above the rounding floor (1e-11) at the
    // orders the knob chooses (from tolerance.hpp's lowest_order), of every
    // set or of the one-signed ones alone.
    const auto ratio = [](double theta) { return theta / (2 - theta); };
    const auto counted = [](const Point& pt, bool one_signed_only) {
        return pt.e_l2 > 1e-11 && pt.p >= poisson::detail::lowest_order(3) && (pt.one_signed || !one_signed_only);
    };
    const auto excess = [&](const Point& pt, double alpha) {
        return std::max(pt.e_l2, pt.phi_l2) / std::pow(alpha * ratio(pt.theta), pt.p + 1);
    };
    const auto fit_envelope = [&](bool one_signed_only) {
        const auto envelope = [&](double alpha) {
            double c = 0;
            for (const Point& pt : points)
                if (counted(pt, one_signed_only)) c = std::max(c, excess(pt, alpha));
            return c;
        };
        double alpha = 1, c = envelope(1), best = std::numeric_limits<double>::infinity();
        for (int i = 500; i <= 1300; ++i) {
            const double a = i / 1000.0, ca = envelope(a);
            double sum = 0;
            for (const Point& pt : points)
                if (counted(pt, one_signed_only)) sum += std::log(ca / excess(pt, a));
            if (sum < best) {
                best = sum;
                alpha = a;
                c = ca;
            }
        }
        return std::pair{alpha, c};
    };
    const auto [alpha, c] = fit_envelope(false);
    const auto [alpha_one, c_one] = fit_envelope(true);
    // Below the lowest order: the largest measured/model of tolerance.hpp's constants.
    const poisson::detail::Calibration in_use = poisson::detail::calibration[1];
    double below = 0;
    std::string below_at;
    for (const Point& pt : points)
        if (pt.e_l2 > 1e-11 && pt.p < poisson::detail::lowest_order(3)) {
            const double x = excess(pt, in_use.alpha) / in_use.c;
            if (x > below) {
                below = x;
                char at[120];
                std::snprintf(at, sizeof at, "%s, theta %.2f, p = %d", pt.set.c_str(), pt.theta, pt.p);
                below_at = at;
            }
        }
    std::printf("one-signed sets alone: alpha %.3f, C %.3g; below p = %d the largest measured/model %.3g (%s)\n",
                alpha_one, c_one, poisson::detail::lowest_order(3), below, below_at.c_str());
    // Cost fit (uniform set): t = n(theta) + b (p + 1)^k theta^-j, least
    // squares of (model - t)/t (rows divided by t), for each (k, j); the one
    // with the smallest largest deviation.
    std::vector<double> thetas;
    for (const Point& pt : points)
        if (pt.set == "uniform 1e5" && std::find(thetas.begin(), thetas.end(), pt.theta) == thetas.end())
            thetas.push_back(pt.theta);
    const auto nt = static_cast<Eigen::Index>(thetas.size());
    struct Fit {
        int k = 0, j = 0;
        Eigen::VectorXd x;  // n(theta) per theta, then b
        double deviation = std::numeric_limits<double>::infinity();
    };
    const auto fit = [&](int k, int j) {
        std::vector<const Point*> rows;
        for (const Point& pt : points)
            if (pt.set == "uniform 1e5") rows.push_back(&pt);
        Eigen::MatrixXd a = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(rows.size()), nt + 1);
        const Eigen::VectorXd ones = Eigen::VectorXd::Ones(a.rows());
        for (Eigen::Index r = 0; r < a.rows(); ++r) {
            const Point& pt = *rows[static_cast<std::size_t>(r)];
            const auto t = std::find(thetas.begin(), thetas.end(), pt.theta) - thetas.begin();
            a(r, t) = 1 / pt.cpu_s;
            a(r, nt) = std::pow(pt.p + 1.0, k) * std::pow(pt.theta, -j) / pt.cpu_s;
        }
        Fit f{k, j, a.colPivHouseholderQr().solve(ones), 0};
        f.deviation = (a * f.x - ones).cwiseAbs().maxCoeff();
        return f;
    };
    Fit cost;
    for (int k = 3; k <= 6; ++k)
        for (int j = 1; j <= 4; ++j)
            if (Fit f = fit(k, j); f.deviation < cost.deviation) cost = f;
    std::string near;
    for (Eigen::Index t = 0; t < nt; ++t) {
        char cell[64];
        std::snprintf(cell, sizeof cell, "%s%.2f: %.4g s", t ? ", " : "", thetas[static_cast<std::size_t>(t)], cost.x(t));
        near += cell;
    }
    std::printf("fit: alpha %.3f, C %.3g; cost n(theta) + b (p + 1)^%d theta^-%d, n = {%s}, b %.4g s (max deviation %.3f)\n",
                alpha, c, cost.k, cost.j, near.c_str(), cost.x(nt), cost.deviation);
    if (md.empty()) return 0;
    std::ofstream out(md + ".tmp");
    out << "# knob_calibration results\n\nGenerated by `cmake --build build --target bench-knob` "
        << "(bench/knob_calibration.cpp), -O3 -march=native, one thread, process CPU seconds of one evaluation at "
        << "all sources. Charges: neutral (uniform in [-0.5, 0.5]) in the uniform 1e5 set and the blob, one-signed in "
        << "the uniform 1e5 positive set (uniform in [0, 1]) and the Plummer sphere (equal masses). E, phi: relative "
        << "L2 errors against direct summation (uniform sets: at the first 1000 points; blob: at all 5000; Plummer: "
        << "at the first 2000). Load (/proc/loadavg): before `" << before << "`, after `" << after << "`.\n\n"
        << "Envelope of max(E, phi) by C (alpha theta/(2 - theta))^(p+1) over the errors above 1e-11 at p >= "
        << poisson::detail::lowest_order(3) << " (the knob's lowest order), every set: **alpha = " << alpha << ", C = " << c
        << "** (C the largest measured ratio at that alpha; alpha the one with the smallest summed "
        << "log(model/measured)); the one-signed sets alone: alpha = " << alpha_one << ", C = " << c_one
        << ". Below p = " << poisson::detail::lowest_order(3) << " the largest measured error over tolerance.hpp's model: **"
        << below << "** (" << below_at << "). Times of the uniform set fitted to n(theta) + b (p + 1)^k "
        << "theta^-j (least squares of the relative deviation; (k, j) in {3..6} x {1..4} with the smallest largest "
        << "deviation): **k = " << cost.k << ", j = " << cost.j << ", n = {" << near << "}, b = " << cost.x(nt)
        << " s**, largest deviation " << cost.deviation
        << ".\n\n| set | theta | p | CPU s | E rel. L2 | phi rel. L2 |\n|---|--:|--:|--:|--:|--:|\n";
    for (const Point& pt : points) {
        char row[200];
        std::snprintf(row, sizeof row, "| %s | %.2f | %d | %.3f | %.3g | %.3g |\n", pt.set.c_str(), pt.theta, pt.p,
                      pt.cpu_s, pt.e_l2, pt.phi_l2);
        out << row;
    }
    out.close();
    std::rename((md + ".tmp").c_str(), md.c_str());
    return 0;
}
