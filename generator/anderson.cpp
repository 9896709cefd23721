#include "anderson.hpp"

#include "error.hpp"
#include "linear_solve.hpp"
#include "radial.hpp"
#include "spec.hpp"

namespace mollify::gen {

Laurent one_minus_r2_power(int n) {
    Laurent p(Q(1));
    const Laurent u = Laurent(Q(1)) - Laurent::monomial(Q(1), 2);
    for (int i = 0; i < n; ++i) p = p * u;
    return p;
}

namespace {

// int_0^1 r^power (1 - r^2)^n dr, exactly.
Q radial_moment_of_power(int power, int n) {
    Q unused;
    const Laurent F = (one_minus_r2_power(n) * Laurent::monomial(Q(1), power)).antiderivative(&unused);
    return F(Q(1)) - F(Q(0));
}

}  // namespace

ExponentMethod exponent_method(int M, int order, int dim) {
    if (M < 1 || M > max_mollifier_M) fail("mollifier exponent M = " + std::to_string(M) + " is outside 1.." + std::to_string(max_mollifier_M));
    if (order < 2 || order > max_mollifier_order || order % 2 != 0)
        fail("mollifier order " + std::to_string(order) + " is not an even number in 2.." + std::to_string(max_mollifier_order));
    if (dim < 1 || dim > 3) fail("dimension " + std::to_string(dim) + " is outside 1..3");
    const int K = order / 2;
    // Rows: mass (k = 0) and moments r^(2k), k = 1..K-1; unknowns beta'_j
    // with B = beta'_j/omega_D (1-r^2)^(M+j).
    Matrix A(static_cast<std::size_t>(K), std::vector<Q>(static_cast<std::size_t>(K)));
    std::vector<Q> b(static_cast<std::size_t>(K), Q(0));
    for (int k = 0; k < K; ++k)
        for (int j = 0; j < K; ++j)
            A[static_cast<std::size_t>(k)][static_cast<std::size_t>(j)] = radial_moment_of_power(dim - 1 + 2 * k, M + j);
    b[0] = 1;
    const std::vector<Q> beta = solve(A, b);
    ExponentMethod e;
    e.normalisation = sphere_measure(dim).inverse() * beta[0];
    for (const Q& bj : beta) e.alpha.push_back(bj / beta[0]);
    return e;
}

}  // namespace mollify::gen
