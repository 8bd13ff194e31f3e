!> Plain-Fortran test harness: checks with tolerances, counts, and a closing summary line.
! SPDX-License-Identifier: MIT
!
! Usage: call begin_test('name') before a group of checks; check(cond, msg) and
! check_close(actual, expected, msg, rtol, atol); finish_tests() prints
! "<program>: N passed, M failed" and stops with code 1 when M > 0.
module testing
  use, intrinsic :: iso_fortran_env, only: output_unit, real64
  use, intrinsic :: ieee_arithmetic, only: ieee_is_nan, ieee_is_finite
  implicit none
  private
  public :: begin_test, check, check_close, finish_tests, test_count, scratch_dir, clear_failures

  integer, parameter :: dp = real64
  integer :: n_pass = 0, n_fail = 0
  character(len=128) :: current = '(none)'
  character(len=128) :: prog = 'test'

  interface check_close
    module procedure check_close_scalar, check_close_array
  end interface check_close

contains

  !> Name the group of checks that follow (printed with failures).
  subroutine begin_test(name)
    character(len=*), intent(in) :: name  !! group name
    current = name
  end subroutine begin_test

  !> Pass when cond is true.
  subroutine check(cond, msg)
    logical, intent(in) :: cond           !! condition that must hold
    character(len=*), intent(in) :: msg   !! what is checked
    if (cond) then
      n_pass = n_pass + 1
    else
      n_fail = n_fail + 1
      write(output_unit, '(5a)') 'FAIL [', trim(current), ']: ', msg
    end if
  end subroutine check

  !> Pass when |a - e| <= max(atol, rtol*|e|); NaN or Inf in a, and NaN in e, fail.
  subroutine check_close_scalar(a, e, msg, rtol, atol)
    real(dp), intent(in) :: a                 !! actual
    real(dp), intent(in) :: e                 !! expected
    character(len=*), intent(in) :: msg       !! what is checked
    real(dp), intent(in), optional :: rtol    !! relative tolerance (default 0)
    real(dp), intent(in), optional :: atol    !! absolute tolerance (default 0)
    call check_close_array([a], [e], msg, rtol, atol)
  end subroutine check_close_scalar

  !> Element-wise closeness of two arrays of the same size; reports the first bad index.
  subroutine check_close_array(a, e, msg, rtol, atol)
    real(dp), intent(in) :: a(:)              !! actual
    real(dp), intent(in) :: e(:)              !! expected
    character(len=*), intent(in) :: msg       !! what is checked
    real(dp), intent(in), optional :: rtol    !! relative tolerance (default 0)
    real(dp), intent(in), optional :: atol    !! absolute tolerance (default 0)
    real(dp) :: rt, at
    integer :: i
    rt = 0.0_dp; at = 0.0_dp
    if (present(rtol)) rt = rtol
    if (present(atol)) at = atol
    if (size(a) /= size(e)) then
      n_fail = n_fail + 1
      write(output_unit, '(5a,i0,a,i0)') 'FAIL [', trim(current), ']: ', msg, &
        ': size ', size(a), ' /= expected ', size(e)
      return
    end if
    do i = 1, size(a)
      if (ieee_is_nan(a(i)) .or. .not. ieee_is_finite(a(i))) then
        n_fail = n_fail + 1
        write(output_unit, '(5a,i0,a)') 'FAIL [', trim(current), ']: ', msg, &
          ': index ', i, ' is not finite'
        return
      end if
      if (ieee_is_nan(e(i))) then
        n_fail = n_fail + 1
        write(output_unit, '(5a,i0,a)') 'FAIL [', trim(current), ']: ', msg, &
          ': index ', i, ' expected value is NaN'
        return
      end if
      if (abs(a(i) - e(i)) > max(at, rt*abs(e(i)))) then
        n_fail = n_fail + 1
        write(output_unit, '(5a,i0,3(a,es23.15))') 'FAIL [', trim(current), ']: ', msg, &
          ': index ', i, ' actual ', a(i), ' expected ', e(i), ' diff ', a(i) - e(i)
        return
      end if
    end do
    n_pass = n_pass + 1
  end subroutine check_close_array

  !> Number of checks so far (passed, failed).
  subroutine test_count(passed, failed)
    integer, intent(out) :: passed  !! checks passed
    integer, intent(out) :: failed  !! checks failed
    passed = n_pass; failed = n_fail
  end subroutine test_count

  !> Remove n failures from the count (only for the harness self-test, which fails on purpose).
  subroutine clear_failures(n)
    integer, intent(in) :: n  !! failures to forget
    n_fail = n_fail - n
  end subroutine clear_failures

  !> Scratch directory: the first command-line argument, or '.'.
  function scratch_dir() result(dir)
    character(len=:), allocatable :: dir
    character(len=1024) :: arg
    integer :: n
    if (command_argument_count() >= 1) then
      call get_command_argument(1, arg, n)
      dir = trim(arg)
    else
      dir = '.'
    end if
  end function scratch_dir

  !> Print "<name>: N passed, M failed"; error stop 1 when M > 0.
  subroutine finish_tests(name)
    character(len=*), intent(in) :: name  !! test program name
    prog = name
    write(output_unit, '(a,": ",i0," passed, ",i0," failed")') trim(prog), n_pass, n_fail
    flush(output_unit)
    if (n_fail > 0) error stop 1
  end subroutine finish_tests
end module testing
