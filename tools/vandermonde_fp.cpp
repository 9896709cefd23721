// vandermonde-fp — why mollify computes kernel weights exactly.
//
// The weights of a mollifier built from several radii solve a (transposed)
// Vandermonde system.  These systems are notoriously ill-conditioned, so this
// tool measures how many correct digits double precision actually delivers.
//
// Systems (both are solved exactly over Q and in double precision with Eigen):
//
//  (a) Franz, Prop. 4.24.  For distinct radii a_1..a_m > 0 the weights w_j of
//      Phi = sum_j w_j psi_{a_j} with unit mass and vanishing even moments
//      below order 2m solve
//          sum_j w_j a_j^(2k) = [k == 0],            k = 0..m-1,
//      with closed form  w_j = prod_{k != j} a_k^2 / (a_k^2 - a_j^2);
//      for equidistant radii a_j = j/m this is
//          w_j = (-1)^(j-1) * 2 (m!)^2 / ((m+j)! (m-j)!).
//
//  (b) Anderson, eq. (26) with beta = 1: the M x M system A c = b with
//      A[i][k] = k^i (rows i = 0..M-1, columns k = 1..M), b = (-1, 0, ..., 0).
//
// For every case the table reports
//  - cond:            sigma_max / sigma_min of the *double* matrix handed to
//                     Eigen and of the exact matrix, both computed by Eigen's
//                     JacobiSVD in 100-digit MPFR arithmetic (a double or long
//                     double SVD saturates near 1/eps and would hide how bad the
//                     exact matrices really are);
//  - digits(weights): -log10(max_j |w_j^double - w_j^exact| / max_j |w_j^exact|);
//  - digits(moments): the double weights are converted *exactly* to rationals and
//                     the residual A_exact w - b is evaluated exactly (for (a):
//                     the moments sum_j w_j a_j^(2k) with the exact radii);
//                     reported is -log10(max_k |residual_k|).
// Digits are capped at 17; a negative value means the error exceeds the scale.
// "n/a" means the double solver returned non-finite numbers.

#include "linear_solve.hpp"
#include "number.hpp"
#include "spec.hpp"
#include "vandermonde.hpp"

#include <CLI/CLI.hpp>
#include <Eigen/Dense>
#include <Eigen/SVD>
#include <boost/multiprecision/eigen.hpp>
#include <boost/multiprecision/gmp.hpp>
#include <boost/multiprecision/mpfr.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <iostream>
#include <limits>
#include <numbers>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

namespace mp = boost::multiprecision;
using Rational = mp::mpq_rational;
using BigFloat = mp::number<mp::mpfr_float_backend<100>, mp::et_off>;
using RVector = std::vector<Rational>;
using RMatrix = std::vector<RVector>;  // row-major: RMatrix[row][col]

constexpr double kDigitCap = 17.0;

void require(bool ok, const std::string& what) {
    if (!ok) throw std::logic_error("check failed: " + what);
}

Rational abs_q(const Rational& x) { return x < 0 ? Rational(-x) : x; }

// The exact side is mollify's own exact core (generator/): linear_solve.hpp,
// vandermonde.hpp; this tool only adds the double-precision side.
using mollify::gen::equidistant_weights;
using mollify::gen::moment_matrix;
using mollify::gen::solve;
using mollify::gen::vandermonde_weights;

RVector residual_exact(const RMatrix& A, const RVector& x, const RVector& b) {
    RVector r(b.size());
    for (std::size_t i = 0; i < b.size(); ++i) {
        Rational s = -b[i];
        for (std::size_t k = 0; k < x.size(); ++k) s += A[i][k] * x[k];
        r[i] = s;
    }
    return r;
}

Rational max_abs(const RVector& v) {
    Rational m = 0;
    for (const auto& x : v) m = std::max(m, abs_q(x));
    return m;
}

// ---------------------------------------------------------------------------
// One test case: exact matrix/rhs, the double matrix actually handed to Eigen.

struct Case {
    std::string system;
    std::string family;
    int n = 0;
    RMatrix exact_A;
    RVector exact_b;
    Eigen::MatrixXd double_A;
    RVector exact_solution;
};

Eigen::VectorXd to_double(const RVector& v) {
    Eigen::VectorXd d(static_cast<Eigen::Index>(v.size()));
    for (std::size_t i = 0; i < v.size(); ++i) d(static_cast<Eigen::Index>(i)) = v[i].convert_to<double>();
    return d;
}

// ---------------------------------------------------------------------------
// (a) Franz, Prop. 4.24: radius families (all radii exact rationals).

struct RadiusFamily {
    std::string name;
    std::function<RVector(int)> radii;  // m -> a_1..a_m
};

std::vector<RadiusFamily> radius_families() {
    return {
        {"equidistant j/m", [](int m) { return mollify::gen::equidistant_radii(m); }},
        {"clustered 1-(m-j)/10^2",
         [](int m) {
             RVector a;
             for (int j = 1; j <= m; ++j) a.push_back(1 - Rational(m - j, 100));
             return a;
         }},
        {"clustered 1-(m-j)/10^4",
         [](int m) {
             RVector a;
             for (int j = 1; j <= m; ++j) a.push_back(1 - Rational(m - j, 10000));
             return a;
         }},
        // Chebyshev nodes cos((2j-1) pi / (4m)) in (0,1), rounded to 6 decimals.
        {"Chebyshev cos((2j-1)pi/4m), 6 dec.",
         [](int m) {
             RVector a;
             for (int j = m; j >= 1; --j) {  // ascending order
                 const double c = std::cos((2.0 * j - 1.0) * std::numbers::pi / (4.0 * m));
                 a.emplace_back(static_cast<long>(std::lround(c * 1e6)), 1000000L);
             }
             return a;
         }},
    };
}

Case franz_case(const RadiusFamily& fam, int m) {
    const RVector a = fam.radii(m);
    require(static_cast<int>(a.size()) == m, "family yields m radii");
    for (std::size_t j = 0; j < a.size(); ++j) {
        require(a[j] > 0, fam.name + ": radii positive");
        for (std::size_t k = 0; k < j; ++k) require(a[j] != a[k], fam.name + ": radii distinct");
    }

    Case c{"Franz 4.24", fam.name, m, RMatrix(m, RVector(m)), RVector(m), Eigen::MatrixXd(m, m), {}};
    c.exact_A = moment_matrix(a);
    for (int k = 0; k < m; ++k) c.exact_b[k] = (k == 0) ? 1 : 0;
    // double matrix from the radii rounded to double; powers taken in double
    for (int j = 0; j < m; ++j) {
        const double aj = a[j].convert_to<double>();
        const double a2 = aj * aj;
        double p = 1.0;
        for (int k = 0; k < m; ++k, p *= a2) c.double_A(k, j) = p;
    }

    c.exact_solution = solve(c.exact_A, c.exact_b);
    require(c.exact_solution == vandermonde_weights(a), "Gauss == closed form (Franz 4.24), " + fam.name);
    if (fam.name.starts_with("equidistant"))
        require(c.exact_solution == equidistant_weights(m), "Gauss == factorial formula, m=" + std::to_string(m));
    return c;
}

// ---------------------------------------------------------------------------
// (b) Anderson, eq. (26): A[i][k] = k^i, b = (-1, 0, ..., 0).

Case anderson_case(int M) {
    Case c{"Anderson (26)", "nodes k = 1..M", M, RMatrix(M, RVector(M)), RVector(M), Eigen::MatrixXd(M, M), {}};
    for (int i = 0; i < M; ++i) {
        c.exact_b[i] = (i == 0) ? -1 : 0;
        for (int k = 1; k <= M; ++k) {
            c.exact_A[i][k - 1] = mollify::gen::pow(Rational(k), i);
            c.double_A(i, k - 1) = c.exact_A[i][k - 1].convert_to<double>();  // exact: k^i < 2^53
        }
    }
    c.exact_solution = solve(c.exact_A, c.exact_b);
    return c;
}

// ---------------------------------------------------------------------------
// Measurements.

struct Solver {
    std::string name;
    std::function<Eigen::VectorXd(const Eigen::MatrixXd&, const Eigen::VectorXd&)> solve;
};

std::vector<Solver> solvers() {
    return {
        {"LU", [](const Eigen::MatrixXd& A, const Eigen::VectorXd& b) -> Eigen::VectorXd { return A.partialPivLu().solve(b); }},
        {"FullLU", [](const Eigen::MatrixXd& A, const Eigen::VectorXd& b) -> Eigen::VectorXd { return A.fullPivLu().solve(b); }},
        {"QR", [](const Eigen::MatrixXd& A, const Eigen::VectorXd& b) -> Eigen::VectorXd { return A.colPivHouseholderQr().solve(b); }},
    };
}

// -log10(err / scale), capped at kDigitCap
double digits(const Rational& err, const Rational& scale) {
    if (err == 0) return kDigitCap;
    const BigFloat ratio = BigFloat(err) / BigFloat(scale);
    return std::min(kDigitCap, -mp::log10(ratio).convert_to<double>());
}

struct Accuracy {
    std::optional<double> weights;
    std::optional<double> moments;
};

Accuracy measure(const Case& c, const Solver& s) {
    const Eigen::VectorXd w = s.solve(c.double_A, to_double(c.exact_b));
    if (!w.allFinite()) return {};
    RVector wq(static_cast<std::size_t>(c.n));
    for (int j = 0; j < c.n; ++j) wq[j] = Rational(w(j));  // exact conversion (mpq_set_d)
    RVector diff(wq.size());
    for (std::size_t j = 0; j < wq.size(); ++j) diff[j] = wq[j] - c.exact_solution[j];
    return {digits(max_abs(diff), max_abs(c.exact_solution)),
            digits(max_abs(residual_exact(c.exact_A, wq, c.exact_b)), Rational(1))};
}

using BigMatrix = Eigen::Matrix<BigFloat, Eigen::Dynamic, Eigen::Dynamic>;

// sigma_max / sigma_min, SVD in 100-digit arithmetic
double condition_number(const BigMatrix& B) {
    Eigen::JacobiSVD<BigMatrix> svd(B);
    const auto& sv = svd.singularValues();
    const BigFloat smin = sv(sv.size() - 1);
    if (smin == 0) return std::numeric_limits<double>::infinity();
    return (sv(0) / smin).convert_to<double>();
}

BigMatrix to_big(const Eigen::MatrixXd& A) { return A.cast<BigFloat>(); }  // exact

BigMatrix to_big(const RMatrix& A) {
    BigMatrix B(static_cast<Eigen::Index>(A.size()), static_cast<Eigen::Index>(A.size()));
    for (std::size_t i = 0; i < A.size(); ++i)
        for (std::size_t k = 0; k < A[i].size(); ++k)
            B(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(k)) = BigFloat(A[i][k]);
    return B;
}

struct Row {
    std::string system;
    std::string family;
    int n = 0;
    double cond_double = 0;  // of the double matrix handed to Eigen
    double cond_exact = 0;   // of the exact rational matrix
    std::vector<Accuracy> acc;  // one per solver
};

Row evaluate(const Case& c, const std::vector<Solver>& ss) {
    Row r{c.system, c.family, c.n, condition_number(to_big(c.double_A)), condition_number(to_big(c.exact_A)),
          {}};
    for (const auto& s : ss) r.acc.push_back(measure(c, s));
    return r;
}

// ---------------------------------------------------------------------------
// Output.

std::string fmt_digits(const std::optional<double>& d) {
    if (!d) return "n/a";
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.1f", *d);
    if (std::string(buf) == "-0.0") return "0.0";
    return buf;
}

std::string fmt_cond(double c) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.1e", c);
    return buf;
}

void write_markdown(std::ostream& os, const std::vector<Row>& rows, const std::vector<Solver>& ss,
                    const std::string& command) {
    os << "Generated by `" << command << "` (source: tools/vandermonde_fp.cpp; regenerate with "
       << "`cmake --build <build-dir> --target vandermonde-fp-md`); do not edit by hand.\n\n"
       << "# Double precision on the kernel-weight systems\n\n"
       << "(a) Franz Prop. 4.24: sum_j w_j a_j^(2k) = [k==0], k < m.  "
          "(b) Anderson eq. (26): sum_k c_k k^i = -[i==0], k = 1..M.\n"
       << "cond = sigma_max/sigma_min (SVD in 100-digit MPFR) of the double matrix handed to Eigen "
          "and of the exact matrix.  "
          "digits(weights) = -log10(max|w - w_exact| / max|w_exact|); "
          "digits(moments) = -log10(max|A_exact w - b|) evaluated exactly.  "
          "Capped at 17; negative = error larger than the scale.\n\n";
    os << "| system | radii family | m | cond(double A) | cond(exact A) |";
    for (const auto& s : ss) os << " digits(weights) " << s.name << " |";
    for (const auto& s : ss) os << " digits(moments) " << s.name << " |";
    os << "\n|---|---|--:|--:|--:|";
    for (std::size_t i = 0; i < 2 * ss.size(); ++i) os << "--:|";
    os << '\n';
    for (const auto& r : rows) {
        os << "| " << r.system << " | " << r.family << " | " << r.n << " | " << fmt_cond(r.cond_double) << " | "
           << fmt_cond(r.cond_exact) << " |";
        for (const auto& a : r.acc) os << ' ' << fmt_digits(a.weights) << " |";
        for (const auto& a : r.acc) os << ' ' << fmt_digits(a.moments) << " |";
        os << '\n';
    }
}

void write_csv(std::ostream& os, const std::vector<Row>& rows, const std::vector<Solver>& ss) {
    os << "system,radii_family,m,cond_double,cond_exact";
    for (const auto& s : ss) os << ",digits_weights_" << s.name;
    for (const auto& s : ss) os << ",digits_moments_" << s.name;
    os << '\n';
    for (const auto& r : rows) {
        os << '"' << r.system << "\",\"" << r.family << "\"," << r.n << ',' << fmt_cond(r.cond_double) << ','
           << fmt_cond(r.cond_exact);
        for (const auto& a : r.acc) os << ',' << (a.weights ? fmt_digits(a.weights) : "");
        for (const auto& a : r.acc) os << ',' << (a.moments ? fmt_digits(a.moments) : "");
        os << '\n';
    }
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"Measure the digits double precision loses on mollify's kernel-weight (Vandermonde) systems."};
    int max_m = 10;
    std::string csv_path;
    std::string md_path;
    app.add_option("--max-m", max_m, "largest m (resp. M)")->check(CLI::Range(1, 16));
    app.add_option("--csv", csv_path, "also write the table as CSV to this file");
    app.add_option("--md", md_path, "write the Markdown table to this file instead of stdout");
    CLI11_PARSE(app, argc, argv);

    try {
        const auto ss = solvers();
        std::vector<Row> rows;
        for (const auto& fam : radius_families())
            for (int m = 1; m <= max_m; ++m) rows.push_back(evaluate(franz_case(fam, m), ss));
        for (int M = 1; M <= max_m; ++M) rows.push_back(evaluate(anderson_case(M), ss));

        const std::string command =
            "vandermonde-fp" + (max_m == 10 ? std::string() : " --max-m " + std::to_string(max_m));
        if (md_path.empty()) {
            write_markdown(std::cout, rows, ss, command);
        } else {
            std::ofstream md(md_path);
            write_markdown(md, rows, ss, command);
            if (!md) throw std::runtime_error("cannot write " + md_path);
        }
        if (!csv_path.empty()) {
            std::ofstream csv(csv_path);
            write_csv(csv, rows, ss);
            if (!csv) throw std::runtime_error("cannot write " + csv_path);
        }
    } catch (const std::exception& e) {
        std::cerr << "vandermonde-fp: " << e.what() << '\n';
        return 1;
    }
    return 0;
}
