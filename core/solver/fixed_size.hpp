// Run-time sizes to compile-time ones: the solver's small dense kernels are templates over
// their size, so that loops over a handful of parameters unroll completely.
#pragma once

#include <cstdlib>

namespace ccdlane::solver {

constexpr int kMaxFixedSize = 8;

constexpr bool has_fixed_size(int n) { return n >= 1 && n <= kMaxFixedSize; }

// Calls f.template operator()<N>() with N = n, a compile-time constant in each branch.
// n must lie in 1..kMaxFixedSize (has_fixed_size): each caller decides itself what any
// other size means to it (Cholesky: a kernel sized at run time; the Schur elimination:
// none, its layouts always have 1..kMaxLocalParams local parameters). A size outside the
// range is a caller's bug, and stops the program in every build type rather than run a
// kernel of the wrong size over storage it does not fit (the check is the switch's own
// default branch: it costs the dispatch nothing).
template <class F>
decltype(auto) with_fixed_size(int n, F&& f) {
  switch (n) {
    case 1: return f.template operator()<1>();
    case 2: return f.template operator()<2>();
    case 3: return f.template operator()<3>();
    case 4: return f.template operator()<4>();
    case 5: return f.template operator()<5>();
    case 6: return f.template operator()<6>();
    case 7: return f.template operator()<7>();
    case 8: return f.template operator()<8>();
    default: std::abort();
  }
}

}  // namespace ccdlane::solver
