// Part 2 of the tables runtime_forms_test compares (static_case.hpp).
#include "static_case.hpp"

#include <mollify/tables/classic/box_d1_D1.hpp>
#include <mollify/tables/classic/quintic_spline_D1.hpp>
#include <mollify/tables/classic/quintic_spline_D3.hpp>
#include <mollify/tables/combo/m_2_base_mollifier_M_4_D1.hpp>
#include <mollify/tables/combo/m_3_base_mollifier_M_4_D2.hpp>
#include <mollify/tables/combo/m_3_base_wendland_k_2_D3.hpp>
#include <mollify/tables/mollifier/M_1_order_4_D2.hpp>
#include <mollify/tables/wendland/k_0_D3.hpp>
#include <mollify/tables/wendland/k_2_D1.hpp>

namespace mollify::testing {

std::vector<Case> cases_2() {
    namespace tables = mollify::tables;
    return {
        case_of<tables::combo_m_3_base_mollifier_M_4_D2>(),
        case_of<tables::combo_m_2_base_mollifier_M_4_D1>(),
        case_of<tables::mollifier_M_1_order_4_D2>(),
        case_of<tables::wendland_k_0_D3>(),
        case_of<tables::wendland_k_2_D1>(),
        case_of<tables::box_d1_D1>(),
        case_of<tables::combo_m_3_base_wendland_k_2_D3>(),
        // W'/r, the Laplacian and the Hessian part on [1/3, 2/3): q^-1 times
        // a Taylor polynomial in q - 1/2 (Var::shifted with low = -1), with
        // and without low parts of the coefficients
        case_of<tables::quintic_spline_D3>(),
        case_of<tables::quintic_spline_D1>(),
    };
}

}  // namespace mollify::testing
