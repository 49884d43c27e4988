// Pixel loops built for several x86-64 targets, the loader picking the best the CPU has
// (GCC's target_clones, an ifunc); every clone computes the same integers. Debian builds
// for x86-64's baseline (SSE2), where a loop over bytes or 32-bit lanes gets a quarter
// of the width AVX2 gives it, and three-byte pixels cannot be taken apart without SSSE3's
// byte shuffles. Not under ThreadSanitizer: an ifunc's resolver runs while the program
// is being relocated, before TSan's runtime is up, and its instrumented code crashed
// every test program at start. Elsewhere (clang, other CPUs) the loops are built once.
#pragma once

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(__SANITIZE_THREAD__)
#define CCDLANE_PIXEL_LOOP_CLONES __attribute__((target_clones("avx2", "ssse3", "default")))
#else
#define CCDLANE_PIXEL_LOOP_CLONES
#endif
