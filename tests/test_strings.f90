!> Text helpers of messages and the progress line (mpm_strings) against hand-worked values.
! SPDX-License-Identifier: MIT
program test_strings
  use mpm_kinds, only: wp
  use mpm_strings, only: hms, plural, itoa, sci
  use testing, only: begin_test, check, finish_tests
  implicit none
  call begin_test('hms: a duration as h:mm:ss')
  call check(hms(0.0_wp) == '0:00:00', 'zero: '//hms(0.0_wp))
  call check(hms(59.4_wp) == '0:00:59', '59.4 s rounds down: '//hms(59.4_wp))
  call check(hms(59.6_wp) == '0:01:00', '59.6 s rounds up to a minute: '//hms(59.6_wp))
  call check(hms(3725.0_wp) == '1:02:05', '3725 s = 1 h 2 min 5 s: '//hms(3725.0_wp))
  call check(hms(360000.0_wp) == '100:00:00', '100 hours are not wrapped: '//hms(360000.0_wp))
  call check(hms(-5.0_wp) == '0:00:00', 'a negative estimate shows as zero: '//hms(-5.0_wp))
  call begin_test('plural')
  call check(plural(1, 'mirror plane') == '1 mirror plane', plural(1, 'mirror plane'))
  call check(plural(0, 'mirror plane') == '0 mirror planes', plural(0, 'mirror plane'))
  call check(plural(2, 'mirror plane') == '2 mirror planes', plural(2, 'mirror plane'))
  call check(itoa(-12) == '-12', 'itoa(-12) = '//itoa(-12))
  call begin_test('sci: scientific notation that keeps its E')
  call check(sci(2.581e-2_wp, 3) == '2.581E-02', 'two-digit exponent: '//sci(2.581e-2_wp, 3))
  call check(sci(1.0e-300_wp, 3) == '1.000E-300', 'three-digit exponent keeps its E: '// &
             sci(1.0e-300_wp, 3))
  call check(sci(1.26e53_wp, 2) == '1.26E+53', 'positive exponent: '//sci(1.26e53_wp, 2))
  call check(sci(-1.0e300_wp, 2) == '-1.00E+300', 'negative value, exponent 300: '// &
             sci(-1.0e300_wp, 2))
  call check(sci(0.0_wp, 1) == '0.0E+00', 'zero: '//sci(0.0_wp, 1))
  call finish_tests('test_strings')
end program test_strings
