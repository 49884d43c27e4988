// Run-time sizes to compile-time ones: the solver's small dense kernels are templates over
// their size, so that loops over a handful of parameters unroll completely.
#pragma once

namespace ccdlane::solver {

constexpr int kMaxFixedSize = 8;

// Calls f.template operator()<N>() with N = n, a compile-time constant in each branch,
// for n in 1..kMaxFixedSize; for any other n with N = Fallback.
template <int Fallback, class F>
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
    default: return f.template operator()<Fallback>();
  }
}

}  // namespace ccdlane::solver
