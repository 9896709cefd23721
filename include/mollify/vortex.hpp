// mollify's 2D vortex-blob method for the periodic vortex sheet: Krasny's
// algebraic blob and the compact mollifiers of the tables (vortex/blob.hpp),
// direct summation and RK4 (vortex/sheet.hpp), the treecode for compact
// blobs (vortex/sheet_treecode.hpp).
#pragma once

#include <mollify/vortex/blob.hpp>
#include <mollify/vortex/periodic_point_vortex.hpp>
#include <mollify/vortex/sheet.hpp>
#include <mollify/vortex/sheet_treecode.hpp>
