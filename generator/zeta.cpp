#include "zeta.hpp"

#include "error.hpp"

namespace mollify::gen {

std::vector<Q> bernoulli_numbers(int n) {
    if (n < 0) fail("bernoulli_numbers: n = " + std::to_string(n) + " must be >= 0");
    std::vector<Q> b{Q(1)};
    for (int m = 1; m <= n; ++m) {
        Q sum = 0, binom = 1;  // binom(m + 1, k)
        for (int k = 0; k < m; ++k) {
            sum += binom * b[static_cast<std::size_t>(k)];
            binom = binom * Q(m + 1 - k) / Q(k + 1);
        }
        b.push_back(-sum / Q(m + 1));
    }
    return b;
}

Q zeta_even_over_pi_power(int j) {
    if (j < 1) fail("zeta(2j) / pi^(2j): j = " + std::to_string(j) + " must be >= 1");
    const Q b = bernoulli_numbers(2 * j).back();
    Q factorial = 1;
    for (int i = 2; i <= 2 * j; ++i) factorial *= i;
    const Q sign = j % 2 == 1 ? Q(1) : Q(-1);
    return sign * b * pow(Q(2), 2 * j - 1) / factorial;  // (-1)^(j+1) B_2j 2^(2j) / (2 (2j)!)
}

}  // namespace mollify::gen
