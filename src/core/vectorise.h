/* Loops over arrays that GCC vectorises, compiled for more than one instruction set.
 *
 * A function marked WEDGE_VECTORISED is compiled three times, for baseline x86-64 and for
 * the x86-64-v3 (AVX2, FMA) and x86-64-v4 (AVX-512) levels, and the copy the CPU can run is
 * picked when the program is loaded (GCC's target_clones, an ifunc); elsewhere it is an
 * ordinary function. The build stays portable (no -march), and wider vectors serve where the
 * machine has them: AVX-512 has the 64-bit multiplies of the sampler's hashes.
 *
 * Such a function must give the same bits in every copy. That holds for integer arithmetic
 * and for IEEE operations that round once (+ - * / sqrt, conversions) in any vector width;
 * contraction into fused multiply-adds, which would round differently, is off, as -std=c11
 * implies -ffp-contract=off (docs/design.md section 12.4). Marked functions are out of line:
 * the ifunc is called through a pointer, so they should each do a loop's worth of work. */
#ifndef WEDGE_CORE_VECTORISE_H
#define WEDGE_CORE_VECTORISE_H

#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__gnu_linux__)
#define WEDGE_VECTORISED __attribute__((target_clones("default", "arch=x86-64-v3", "arch=x86-64-v4"), noinline))
#else
#define WEDGE_VECTORISED __attribute__((noinline))
#endif

#endif
