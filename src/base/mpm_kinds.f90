!> Working precision and integer kinds for the whole code.
! SPDX-License-Identifier: MIT
module mpm_kinds
  use, intrinsic :: iso_fortran_env, only: real64, int32, int64
  implicit none
  private
  public :: wp, ip, i8

  integer, parameter :: wp = real64  !! working precision of every real
  integer, parameter :: ip = int32   !! default integer kind for indices
  integer, parameter :: i8 = int64   !! counters that may pass 2**31 (particle-steps, bytes)
end module mpm_kinds
