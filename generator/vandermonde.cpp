#include "vandermonde.hpp"

#include "error.hpp"

namespace mollify::gen {

namespace {

void check_distinct_positive(const std::vector<Q>& radii) {
    if (radii.empty()) fail("at least one radius is needed");
    for (std::size_t i = 0; i < radii.size(); ++i) {
        if (radii[i] <= 0) fail("radius " + short_string(radii[i]) + " is not positive");
        for (std::size_t j = 0; j < i; ++j)
            if (radii[i] == radii[j]) fail("radius " + short_string(radii[i]) + " is repeated; radii must be distinct");
    }
}

}  // namespace

Matrix moment_matrix(const std::vector<Q>& radii) {
    const std::size_t m = radii.size();
    Matrix A(m, std::vector<Q>(m));
    for (std::size_t k = 0; k < m; ++k)
        for (std::size_t j = 0; j < m; ++j) A[k][j] = pow(radii[j], 2 * static_cast<int>(k));
    return A;
}

std::vector<Q> vandermonde_weights(const std::vector<Q>& radii) {
    check_distinct_positive(radii);
    std::vector<Q> w(radii.size(), Q(1));
    for (std::size_t j = 0; j < radii.size(); ++j)
        for (std::size_t k = 0; k < radii.size(); ++k)
            if (k != j) {
                const Q ak2 = radii[k] * radii[k];
                w[j] *= ak2 / (ak2 - radii[j] * radii[j]);
            }
    return w;
}

std::vector<Q> vandermonde_weights_by_solve(const std::vector<Q>& radii) {
    check_distinct_positive(radii);
    std::vector<Q> rhs(radii.size(), Q(0));
    rhs[0] = 1;
    return solve(moment_matrix(radii), rhs);
}

std::vector<Q> equidistant_weights(int m) {
    if (m < 1) fail("m = " + std::to_string(m) + " must be at least 1");
    std::vector<Q> w;
    const Z mf = factorial(static_cast<unsigned>(m));
    for (int j = 1; j <= m; ++j) {
        const Q v(2 * mf * mf, factorial(static_cast<unsigned>(m + j)) * factorial(static_cast<unsigned>(m - j)));
        w.push_back(j % 2 == 1 ? v : Q(-v));
    }
    return w;
}

}  // namespace mollify::gen
