#include "linear_solve.hpp"

#include "error.hpp"

namespace mollify::gen {

std::vector<Q> solve(Matrix A, std::vector<Q> b) {
    const std::size_t n = b.size();
    for (std::size_t col = 0; col < n; ++col) {
        std::size_t pivot = col;
        while (pivot < n && A[pivot][col] == 0) ++pivot;
        if (pivot == n) fail("singular linear system (column " + std::to_string(col) + ")");
        std::swap(A[pivot], A[col]);
        std::swap(b[pivot], b[col]);
        for (std::size_t row = col + 1; row < n; ++row) {
            if (A[row][col] == 0) continue;
            const Q f = A[row][col] / A[col][col];
            for (std::size_t j = col; j < n; ++j) A[row][j] -= f * A[col][j];
            b[row] -= f * b[col];
        }
    }
    std::vector<Q> x(n);
    for (std::size_t i = n; i-- > 0;) {
        Q s = b[i];
        for (std::size_t j = i + 1; j < n; ++j) s -= A[i][j] * x[j];
        x[i] = s / A[i][i];
    }
    return x;
}

}  // namespace mollify::gen
