//! The checks that hold each vector kernel to its portable reference, for
//! the test binary `tests/kernels` (behind the `synthetic` feature).
//!
//! They are not `#[test]`s: libtest can only skip a test chosen at compile
//! time, so a kernel test on a CPU without the kernel's features could only
//! print "skipped" and pass. The harness of `tests/kernels` decides at run
//! time instead and reports such a check *ignored*, with the reason (also
//! where `CI` is set: CI machines may lack AVX-512, which is no failure).

use crate::simd::Kernel;

/// One check: its name (as the harness lists it), the kernel whose CPU
/// features it needs, and its body, which panics when the kernel's answer
/// differs from the reference's.
pub struct KernelCheck {
    pub name: &'static str,
    pub kernel: Kernel,
    pub run: fn(),
}

/// Every kernel check.
pub fn kernel_checks() -> Vec<KernelCheck> {
    use crate::count::counts::kernel_checks as counts;
    use crate::count::scan::kernel_checks as scan;
    use crate::png::unfilter::kernel_checks as unfilter;
    let check = |name, kernel, run| KernelCheck { name, kernel, run };
    vec![
        check(
            "count::counts::the_avx2_update_adds_words_and_saturates",
            Kernel::Avx2,
            counts::the_avx2_update_adds_words_and_saturates,
        ),
        check(
            "count::counts::the_avx512_update_adds_words_and_saturates",
            Kernel::Avx512,
            counts::the_avx512_update_adds_words_and_saturates,
        ),
        check(
            "count::scan::the_avx2_kernel_equals_the_portable_kernel",
            Kernel::Avx2,
            scan::the_avx2_kernel_equals_the_portable_kernel,
        ),
        check(
            "count::scan::the_avx512_kernel_equals_the_portable_kernel",
            Kernel::Avx512,
            scan::the_avx512_kernel_equals_the_portable_kernel,
        ),
        check(
            "count::scan::the_kernel_that_tallies_parts_gives_the_separate_passs_pixels_and_solid_angles",
            Kernel::Avx512,
            scan::the_kernel_that_tallies_parts_gives_the_separate_passs_pixels_and_solid_angles,
        ),
        check(
            "count::scan::the_portable_kernels_texel_areas_equal_the_reference_pass",
            Kernel::Portable,
            scan::the_portable_kernels_texel_areas_equal_the_reference_pass,
        ),
        check(
            "count::scan::the_avx2_kernels_texel_areas_equal_the_reference_pass",
            Kernel::Avx2,
            scan::the_avx2_kernels_texel_areas_equal_the_reference_pass,
        ),
        check(
            "count::scan::the_avx512_kernels_texel_areas_equal_the_reference_pass",
            Kernel::Avx512,
            scan::the_avx512_kernels_texel_areas_equal_the_reference_pass,
        ),
        check(
            "png::unfilter::four_rows_side_by_side_equal_rows_one_at_a_time_for_every_filter_mix",
            Kernel::Avx2,
            unfilter::four_rows_side_by_side_equal_rows_one_at_a_time_for_every_filter_mix,
        ),
        check(
            "png::unfilter::eight_rows_side_by_side_equal_rows_one_at_a_time_for_many_filter_mixes",
            Kernel::Avx512,
            unfilter::eight_rows_side_by_side_equal_rows_one_at_a_time_for_many_filter_mixes,
        ),
    ]
}
