#!/usr/bin/env python3
"""Mutation check of the arch layer's tests (tests/test_arch_layer.cpp).

Each mutation breaks one primitive of one family file (kernels/simd_x86.hpp or
kernels/simd_neon.hpp) the way a port or a newer xsimd could: operand order in vmin, the zero a
reduction keeps, ties in rounding, one lane too many in a partial store, and so on (and the
colour twins' sRGB decoder and encoder, kernels/color_formats*.hpp, checked per set like primitives). For each, the
file is edited, reproject_tests is rebuilt in BUILD, the ArchLayer suite runs, and the mutation
counts as caught only if the test named after that primitive fails. The file is restored after
every mutation, whatever happens.

  python3 tests/arch_layer/mutate.py --family x86 --build build
  python3 tests/arch_layer/mutate.py --family neon --build build-arm --runner qemu-aarch64

Exit status 1 if any mutation escapes. Not run by ctest (one rebuild per mutation); its output
for both families is quoted in docs/ARCHITECTURE.md, "The arch layer".
"""
import argparse
import pathlib
import re
import signal
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parents[2]

# (primitive whose test must fail, file, text, replacement)
X86 = [
    ("vmin", "simd_x86_avx2.hpp", "static F min(const F& a, const F& b) { return _mm256_min_ps(a, b); }",
     "static F min(const F& a, const F& b) { return _mm256_min_ps(b, a); }"),
    ("vmax", "simd_x86_sse.hpp", "static F max(const F& a, const F& b) { return _mm_max_ps(a, b); }",
     "static F max(const F& a, const F& b) { return _mm_max_ps(b, a); }"),
    ("vfloor", "simd_x86.hpp", "return X86SetOf<F>::floor(x);", "return X86SetOf<F>::floor(x) + F(0.0f);"),
    ("vdiv", "simd_x86.hpp", "return a / b;", "return a * (F(1.0f) / b);"),
    ("vmadd", "simd_x86.hpp", "return X86SetOf<F>::fmadd(a, b, c);", "return a * b + c;"),
    ("round_to_int", "simd_x86_avx512.hpp", "static I round_to_int(const F& x) { return _mm512_cvtps_epi32(x); }",
     "static I round_to_int(const F& x) { return _mm512_cvttps_epi32(x); }"),
    ("bits_of", "simd_x86_avx2.hpp", "static I bits_of(const F& v) { return _mm256_castps_si256(v); }",
     "static I bits_of(const F& v) { return _mm256_cvtps_epi32(v); }"),
    ("byte_lanes", "simd_x86_avx2.hpp", "if constexpr (Byte == 3) return _mm256_srli_epi32(w, 24);",
     "if constexpr (Byte == 3) return _mm256_srli_epi32(w, 23);"),
    ("byte_lanes", "simd_x86_avx512.hpp", "_mm512_slli_epi32(w, 24 - 8 * Byte), 24)", "_mm512_slli_epi32(w, 24 - 8 * Byte), 23)"),
    ("gather", "simd_x86_avx2.hpp", "_mm256_i32gather_ps(base, index, 4)", "_mm256_i32gather_ps(base + 1, index, 4)"),
    # The sRGB decoder (AVX-512): two parts swapped; an index of four bits. Its encoder's estimate:
    # no margin round a rounding boundary; a coefficient 4e-6 off (1e-3 codes at the top). The
    # rgba8_srgb blend: the far pairs never blended otherwise, or one channel's never merged, or
    # merged into the wrong channel; the second-order rule one code looser, its offset rounded;
    # with permutes, the estimate's test skipped. Its rule for a
    # near pair: one code looser in the scalar rule (which the SIMD twins are held to), the + 4's
    # mask letting in the next byte's bit, the alpha flagged, a difference at the limit taken as far.
    ("srgb_decode", "color_formats_simd.hpp", "xsimd::select(bit5, part[7], part[6])", "xsimd::select(bit5, part[6], part[7])"),
    ("srgb_decode", "color_formats_simd.hpp", "index_for_two_registers<Arch>(lanes, bytes & I(31));",
     "index_for_two_registers<Arch>(lanes, bytes & I(15));"),
    ("srgb_encode", "color_formats.hpp", "kSrgbEstimateMargin = 0x1p-13f;", "kSrgbEstimateMargin = 0x1p-24f;"),
    ("srgb_encode", "color_formats.hpp", "0x1.aaa4e4p-2f, 0x1.000004p+0f}", "0x1.aaa4e4p-2f, 0x1.000040p+0f}"),
    ("srgb_blend", "color_formats_simd.hpp", "if (!xsimd::any(far != I(0))) return fixed;", "if (true) return fixed;"),
    ("srgb_blend", "color_formats_simd.hpp", "const I far_c = far & I(0xff << (8 * c));", "const I far_c = far & I(0xff << (8 * c)) & I(0xffff);"),
    ("srgb_blend", "color_formats_simd.hpp", "out = (out & ~far_c) | ((code << (8 * c)) & far_c);",
     "out = (out & ~far_c) | ((code << (8 * (2 - c))) & far_c);"),
    ("srgb_blend", "color_formats_simd.hpp", "const F limit = vmin(a, b) + F(9.0f);", "const F limit = vmin(a, b) + F(10.0f);"),
    ("srgb_blend", "color_formats_simd.hpp", "x + F(14.025f));", "x + F(14.0f));"),
    ("srgb_blend", "color_formats_simd.hpp", "if (!xsimd::any(srgb_estimate_lanes<Arch, Fma>(*f.srgb, linear, code))) return code;",
     "if (true) return code;"),
    ("srgb_far_pairs", "codes.hpp", "return high - low <= 10 + ((low + 4) >> 3);", "return high - low <= 11 + ((low + 4) >> 3);"),
    ("srgb_far_pairs", "simd_x86_avx2.hpp", "_mm256_set1_epi8(4)), 3), _mm256_set1_epi8(0x1f)),", "_mm256_set1_epi8(4)), 3), _mm256_set1_epi8(0x3f)),"),
    ("srgb_far_pairs", "simd_x86_avx512.hpp", "_mm512_mask_cmpgt_epu8_mask(0x7777777777777777ull,", "_mm512_mask_cmpgt_epu8_mask(0xf777777777777777ull,"),
    ("srgb_far_pairs", "simd_x86_sse.hpp", "_mm_cmpeq_epi8(_mm_subs_epu8(difference, limit), _mm_setzero_si128());",
     "_mm_cmpeq_epi8(_mm_subs_epu8(difference, _mm_sub_epi8(limit, _mm_set1_epi8(1))), _mm_setzero_si128());"),
    ("lane_extreme", "simd_x86.hpp", "lane_extreme_key<Max>(total_order_key(bits_of<Arch>(v)))",
     "lane_extreme_key<Max>(bits_of<Arch>(v))"),
    ("lane_extreme", "simd_x86_avx512.hpp", "return Max ? _mm512_reduce_max_epi32(k) : _mm512_reduce_min_epi32(k);",
     "return Max ? _mm512_reduce_max_epi32(k) : _mm512_reduce_max_epi32(k);"),
    ("first_lane", "simd_x86_avx2.hpp", "return _mm256_cvtss_f32(v);", "return _mm_cvtss_f32(_mm256_extractf128_ps(v, 1));"),
    ("shift_in_first", "simd_x86_avx2.hpp", "_mm256_setr_epi32(0, 0, 1, 2, 3, 4, 5, 6)", "_mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7)"),
    ("shift_in_first", "simd_x86_sse.hpp", "_mm_shuffle_ps(first, first, 0)), 12)", "_mm_shuffle_ps(first, first, 0)), 8)"),
    ("shift_in_first", "simd_x86_avx512.hpp", "_mm512_castps_si512(v), low, 15)", "_mm512_castps_si512(v), low, 14)"),
    ("permute", "simd_x86_avx512.hpp", "return _mm512_permutexvar_ps(lanes.index, v);",
     "return _mm512_permutexvar_ps(_mm512_xor_si512(lanes.index, _mm512_set1_epi32(1)), v);"),
    ("permute_two_registers", "simd_x86_avx2.hpp", "_mm256_cmpgt_epi32(index, _mm256_set1_epi32(7))",
     "_mm256_cmpgt_epi32(index, _mm256_set1_epi32(8))"),
    ("store_first_lanes", "simd_x86_avx2.hpp", "_mm256_cmpgt_epi32(_mm256_set1_epi32(count), lanes)",
     "_mm256_cmpgt_epi32(_mm256_set1_epi32(count + 1), lanes)"),
    ("store_first_lanes", "simd_x86_sse.hpp", "_mm_blendv_ps(_mm_loadu_ps(out), value, write)", "_mm_blendv_ps(value, _mm_loadu_ps(out), write)"),
    ("store_bytes", "simd_x86_avx2.hpp", "_mm_storel_epi64(reinterpret_cast<__m128i*>(out), _mm_packus_epi16(halves, halves));",
     "_mm_storeu_si128(reinterpret_cast<__m128i*>(out), _mm_packus_epi16(halves, halves));"),
    ("load_u16", "simd_x86_avx2.hpp", "return _mm256_cvtepu16_epi32(", "return _mm256_cvtepi16_epi32("),
    ("store_u16", "simd_x86_avx2.hpp", "packed = _mm_blendv_epi8(_mm_loadu_si128(reinterpret_cast<const __m128i*>(out)), packed, keep);",
     "packed = _mm_blendv_epi8(packed, _mm_loadu_si128(reinterpret_cast<const __m128i*>(out)), keep);"),
    ("lerp4", "simd_x86.hpp", "return _mm_fmadd_ps(frac, _mm_sub_ps(c1, c0), c0);", "return _mm_fmadd_ps(frac, c1, _mm_fnmadd_ps(frac, c0, c0));"),
    ("blend_rgba8_q15", "simd_x86_avx2.hpp", "_mm256_broadcastsi128_si256(_mm_setr_epi8(8, 9, 8, 9, 8, 9, 8, 9, 12, 13, 12, 13, 12, 13, 12, 13))",
     "_mm256_broadcastsi128_si256(_mm_setr_epi8(8, 9, 8, 9, 8, 9, 8, 9, 8, 9, 12, 13, 12, 13, 12, 13))"),
    ("blend_rgba8_q15", "simd_x86_sse.hpp", "const __m128i r1 = _mm_add_epi16(a1, _mm_mulhrs_epi16(d1, _mm_shuffle_epi8(weight, second)));",
     "const __m128i r1 = _mm_add_epi16(a1, _mm_mulhi_epi16(d1, _mm_shuffle_epi8(weight, second)));"),
    ("store_half4", "simd_x86.hpp", "_mm_cvtps_ph(value, _MM_FROUND_TO_NEAREST_INT | _MM_FROUND_NO_EXC)",
     "_mm_cvtps_ph(value, _MM_FROUND_TO_ZERO | _MM_FROUND_NO_EXC)"),
    ("pixel4", "simd_x86.hpp", "inline Pixel4 pixel4_zero() { return _mm_setzero_ps(); }",
     "inline Pixel4 pixel4_zero() { return _mm_set1_ps(-0.0f); }"),
]
NEON = [
    ("vmin", "simd_neon.hpp", "return vbslq_f32(vcltq_f32(a, b), a, b);", "return vminq_f32(a, b);"),
    ("vmax", "simd_neon.hpp", "return vbslq_f32(vcgtq_f32(a, b), a, b);", "return vbslq_f32(vcgeq_f32(a, b), a, b);"),
    ("vfloor", "simd_neon.hpp", "return vrndmq_f32(x);", "return vrndq_f32(x);"),
    ("vdiv", "simd_neon.hpp", "return vdivq_f32(a, b);", "return vmulq_f32(a, vdivq_f32(vdupq_n_f32(1.0f), b));"),
    ("vmadd", "simd_neon.hpp", "return vfmaq_f32(c, a, b);  // c + a b, one rounding", "return vaddq_f32(c, vmulq_f32(a, b));"),
    ("round_to_int", "simd_neon.hpp", "return vcvtnq_s32_f32(x);", "return vcvtaq_s32_f32(x);"),
    ("float_bits", "simd_neon.hpp", "return vreinterpretq_f32_s32(v);", "return vcvtq_f32_s32(v);"),
    ("byte_lanes", "simd_neon.hpp", "return vreinterpretq_s32_u32(vshrq_n_u32(vreinterpretq_u32_s32(w), 24));",
     "return vreinterpretq_s32_s32(vshrq_n_s32(w, 24));"),
    ("gather", "simd_neon.hpp", "std::memcpy(&value[i], base + at[i], sizeof(float));",
     "std::memcpy(&value[i], base + at[i ^ 1], sizeof(float));"),
    ("lane_extreme", "simd_neon.hpp", "const std::int32_t extreme = Max ? vmaxvq_s32(key) : vminvq_s32(key);",
     "const std::int32_t extreme = Max ? vmaxvq_s32(bits) : vminvq_s32(bits);"),
    ("first_lane", "simd_neon.hpp", "return vgetq_lane_f32(v, 0);", "return vgetq_lane_f32(v, 1);"),
    ("shift_in_first", "simd_neon.hpp", "return vextq_f32(vdupq_n_f32(first), v, 3);", "return vextq_f32(v, vdupq_n_f32(first), 3);"),
    ("permute", "simd_neon.hpp", "vdupq_n_u32(0x03020100u)", "vdupq_n_u32(0x03020001u)"),
    ("permute_two_registers", "simd_neon.hpp", "table.val[1] = vreinterpretq_u8_f32(high);", "table.val[1] = vreinterpretq_u8_f32(low);"),
    ("store_first_lanes", "simd_neon.hpp", "F::load_aligned(lanes) < F(static_cast<float>(count))",
     "F::load_aligned(lanes) <= F(static_cast<float>(count))"),
    ("store_bytes", "simd_neon.hpp", "std::memcpy(out, &four, 4);", "std::memcpy(out, &four, 3);"),
    ("load_u16", "simd_neon.hpp", "return vreinterpretq_s32_u32(vmovl_u16(vcreate_u16(codes)));",
     "return vmovl_s16(vcreate_s16(codes));"),
    ("store_u16", "simd_neon.hpp", "packed = vbsl_u16(vmovn_u32(static_cast<uint32x4_t>(write)), packed, vcreate_u16(before));",
     "packed = vbsl_u16(vmovn_u32(static_cast<uint32x4_t>(write)), vcreate_u16(before), packed);"),
    ("lerp4", "simd_neon.hpp", "return vfmaq_f32(c0, frac, vsubq_f32(c1, c0));", "return vaddq_f32(c0, vmulq_f32(frac, vsubq_f32(c1, c0)));"),
    ("blend_rgba8_q15", "simd_neon.hpp", "const uint8x8_t r1 = vqmovun_s16(vaddq_s16(a1, vqrdmulhq_s16(d1, w1)));",
     "const uint8x8_t r1 = vqmovun_s16(vaddq_s16(a1, vqdmulhq_s16(d1, w1)));"),
    ("srgb_far_pairs", "simd_neon.hpp", "vcgtq_u8(vabdq_u8(a, b), limit)", "vcgeq_u8(vabdq_u8(a, b), limit)"),
    ("load_half4", "simd_neon.hpp", "return vcvt_f32_f16(vreinterpret_f16_u64(vcreate_u64(halves)));",
     "return vcvt_f32_f16(vreinterpret_f16_u64(vcreate_u64(halves & 0xffffffffffff7fffull)));"),
]


def run(cmd, **kw):
    return subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True, **kw)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--family", choices=["x86", "neon"], required=True)
    parser.add_argument("--build", required=True, help="a configured build directory of that family")
    parser.add_argument("--runner", default="", help="e.g. qemu-aarch64 for the neon family")
    parser.add_argument("--only", default="", help="regex over the primitive names")
    args = parser.parse_args()
    signal.signal(signal.SIGTERM, lambda *_: sys.exit(143))  # a kill still restores the file (finally below)
    mutations = [m for m in (X86 if args.family == "x86" else NEON) if re.search(args.only, m[0])]
    escaped = []
    for primitive, name, text, replacement in mutations:
        path = ROOT / "kernels" / name
        original = path.read_text()
        if original.count(text) != 1:
            sys.exit(f"{name}: the text to mutate for {primitive} is not there exactly once: {text}")
        try:
            path.write_text(original.replace(text, replacement))
            build = run(["cmake", "--build", args.build, "--target", "reproject_tests", "-j2"])
            if build.returncode != 0:
                verdict = "caught at compile time"
                failed = []
            else:
                test = run(args.runner.split() + [f"{args.build}/tests/reproject_tests", "--gtest_filter=EverySet/ArchLayer.*"])
                failed = sorted(set(re.findall(r"\[  FAILED  \] EverySet/ArchLayer\.(\w+)/(\w+)", test.stdout)))
                names = {f"{p}/{s}" for p, s in failed}
                verdict = "caught" if any(p == primitive for p, _ in failed) else "ESCAPED"
                failed = sorted(names)
        finally:
            path.write_text(original)
        print(f"{verdict:>22}  {primitive:<22} {name}: {text.strip()[:60]!r}  failed: {', '.join(failed) or '-'}", flush=True)
        if verdict == "ESCAPED":
            escaped.append(primitive)
    run(["cmake", "--build", args.build, "--target", "reproject_tests", "-j2"])  # back to the real code
    print(f"{len(mutations) - len(escaped)} of {len(mutations)} mutations caught by the test named after the primitive")
    return 1 if escaped else 0


if __name__ == "__main__":
    sys.exit(main())
