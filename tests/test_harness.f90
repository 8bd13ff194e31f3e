!> Self-test of the harness: passing checks pass, failing checks are counted as failures.
! SPDX-License-Identifier: MIT
program test_harness
  use, intrinsic :: iso_fortran_env, only: real64
  use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan
  use testing, only: begin_test, check, check_close, finish_tests, test_count, clear_failures
  implicit none
  integer, parameter :: dp = real64
  integer :: p0, f0, p1, f1
  real(dp) :: nan

  call begin_test('checks that must fail are counted as failures')
  call test_count(p0, f0)
  call check(.false., 'deliberately false (expected FAIL line above is correct)')
  call check_close(1.0_dp, 2.0_dp, 'deliberately far apart', rtol=1e-3_dp)
  nan = ieee_value(nan, ieee_quiet_nan)
  call check_close(nan, 1.0_dp, 'NaN must fail', atol=huge(1.0_dp))
  call check_close(1.0_dp, nan, 'NaN expected must fail', atol=huge(1.0_dp))
  call check_close([1.0_dp, 2.0_dp], [1.0_dp], 'size mismatch must fail', atol=1.0_dp)
  call test_count(p1, f1)
  ! Undo the five deliberate failures by checking them: they must be exactly 5 new failures.
  call reset_expected(f1 - f0, p1 - p0)

  call begin_test('checks that must pass')
  call check(.true., 'true')
  call check_close(1.0_dp, 1.0_dp + 1e-13_dp, 'within rtol', rtol=1e-12_dp)
  call check_close(0.0_dp, 1e-15_dp, 'within atol', atol=1e-14_dp)
  call check_close([1.0_dp, 2.0_dp], [1.0_dp, 2.0_dp], 'arrays equal')
  call finish_tests('test_harness')

contains
  subroutine reset_expected(new_fail, new_pass)
    integer, intent(in) :: new_fail, new_pass
    ! The five deliberate failures must have moved the counts by exactly 5 failures, 0 passes.
    if (new_fail == 5 .and. new_pass == 0) then
      print '(a)', 'test_harness: the 5 deliberate failures above were detected (as they must be)'
      call clear_failures(5)
    else
      print '(a,i0,a,i0)', 'test_harness: deliberate failures not detected: fail +', new_fail, &
        ' pass +', new_pass
      error stop 1
    end if
  end subroutine reset_expected
end program test_harness
