!> The end-of-run energy warning (mpm_advice advice_end_of_run) reads at a glance: silent when the
!! balance closes, else one line of at most about 120 characters that gives the error, says
!! what to set and ends with a doc section (issue 32 item 6).
!! Oracle: the error passed in, printed as a percentage; the line's length and form.
!!   usage: test_messages [SCRATCH]
! SPDX-License-Identifier: MIT
program test_messages
  use mpm_kinds, only: wp
  use mpm_advice, only: advice_end_of_run
  use testing, only: begin_test, check, finish_tests
  implicit none
  character(len=:), allocatable :: msg
  logical :: musl, bodies
  integer :: i

  call begin_test('end-of-run energy warning')
  msg = advice_end_of_run(0.04_wp, 1.0_wp, 0.04_wp, .true., .false.)
  call check(len(msg) == 0, 'a 4 % error draws no warning (the threshold is 5 %)')
  do i = 0, 3
    musl = mod(i, 2) == 0
    bodies = i >= 2
    msg = advice_end_of_run(0.073_wp, 1.0_wp, 0.073_wp, musl, bodies)
    call check(index(msg, '7.30 %') > 0, 'gives the error 7.30 %: '//msg)
    call check(len(msg) <= 120 - len('WARNING [run]: '), 'fits one line of 120 with its prefix: '//msg)
    call check(index(msg, new_line('a')) == 0, 'one line: '//msg)
    call check(index(msg, 'Set ') > 0 .and. index(msg, '(docs/') > 0 .and. &
               msg(len(msg):len(msg)) == ')', 'says what to set and ends with its doc: '//msg)
    call check((index(msg, "'musl'") > 0) .neqv. musl, 'names scheme = musl only where not used: '//msg)
    call check((index(msg, 'body contact') > 0) .eqv. bodies, &
               'names the contact between bodies only with several bodies: '//msg)
  end do
  msg = advice_end_of_run(1.0e9_wp, 1.0_wp, 1.0e7_wp, .true., .false.)
  call check(len(msg) > 0 .and. len(msg) <= 120, 'a huge error still prints in one line: '//msg)
  call finish_tests('test_messages')
end program test_messages
