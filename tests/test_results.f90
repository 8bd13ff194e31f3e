!> The absorber results of a run (mpm_results): stroke, peak and mean force, CFE, SEA and the
!! densification stroke by the energy-efficiency method, from a history.csv written here with a
!! force-approach curve of closed form.
!! Oracle: F(d) = F0 up to d1, F0 + K (d - d1)^2 beyond (a plateau, then densification), so
!! E(d) = F0 d + K (d - d1)^3 / 3 and the efficiency E/F is largest where F^2 = E dF/dd, found
!! here by bisection; the peak is F at the end; a platen driven against a parallel mirror plane
!! (a quarter model) doubles the approach; a platen pair shares it. A fixed platen facing the
!! moving one is its support (its peak and the CFE on it); a spike of the moving platen's force
!! at first contact, 5.9 times the support's peak, is reported in one line with both numbers.
!!   usage: test_results [SCRATCH]
! SPDX-License-Identifier: MIT
program test_results
  use mpm_kinds, only: wp
  use mpm_walls, only: wall_t
  use mpm_results, only: results_t, results_compute, results_warning
  use testing, only: begin_test, check, check_close, finish_tests
  use mpm_strings, only: itoa
  implicit none
  real(wp), parameter :: f0 = 1.0e4_wp, d1 = 0.02_wp, kk = 4.0e8_wp, dmax = 0.04_wp
  character(len=:), allocatable :: dir
  character(len=512) :: arg

  dir = '/tmp'
  if (command_argument_count() > 0) then
    call get_command_argument(1, arg)
    dir = trim(arg)
  end if
  call execute_command_line('mkdir -p '//dir)

  call begin_test('one platen against a fixed one')
  call case_one(.false.)
  call begin_test('a platen against a parallel mirror plane (quarter model)')
  call case_one(.true.)
  call begin_test('a spike of the platen force at first contact')
  call case_spike()
  call begin_test('two platens approaching each other')
  call case_two()
  call begin_test('a plateau with a dip of the force and unloading: no densification')
  call case_dip()
  call begin_test('a section that softens after its first peak: no densification')
  call case_soft()
  call finish_tests('test_results')

contains

  pure real(wp) function force(d)
    real(wp), intent(in) :: d
    force = f0 + kk*max(d - d1, 0.0_wp)**2
  end function force

  pure real(wp) function energy(d)
    real(wp), intent(in) :: d
    energy = f0*d + kk*max(d - d1, 0.0_wp)**3/3.0_wp
  end function energy

  !> The stroke of the largest E/F, by bisection on F^2 - E F' (positive before, negative after).
  real(wp) function densification() result(d)
    real(wp) :: a, b, g
    integer :: it
    a = d1
    b = dmax
    do it = 1, 200
      d = 0.5_wp*(a + b)
      g = force(d)**2 - energy(d)*2.0_wp*kk*(d - d1)
      if (g > 0.0_wp) then
        a = d
      else
        b = d
      end if
    end do
  end function densification

  subroutine write_history(path, nwall, adv, spike)
    character(len=*), intent(in) :: path
    integer, intent(in) :: nwall
    real(wp), intent(in) :: adv            !! each loading wall's share of the approach [-]
    real(wp), intent(in), optional :: spike  !! wall 1's force on the second row [N]
    integer :: u, i, k, n
    real(wp) :: d, f
    n = 4001
    open(newunit=u, file=path, status='replace', action='write')
    write(u, '(a)', advance='no') 'time'
    do k = 1, nwall
      write(u, '(a,i0,a,i0,a,i0,a,i0,a)', advance='no') ',wall', k, '_disp,wall', k, &
        '_force,wall', k, '_fx,wall', k, '_fy'
    end do
    write(u, '(a)') ',kinetic,strain,plastic,external'
    do i = 1, n
      d = dmax*real(i - 1, wp)/real(n - 1, wp)
      write(u, '(es24.16e3)', advance='no') 1.0e-3_wp*d
      do k = 1, nwall
        f = force(d)
        if (present(spike) .and. k == 1 .and. i == 2) f = spike
        write(u, '(4(",",es24.16e3))', advance='no') -adv*d, f, 0.0_wp, f
      end do
      write(u, '(4(",",es24.16e3))') 0.0_wp, 0.0_wp, 0.5_wp*energy(d), energy(d)
    end do
    close(u)
  end subroutine write_history

  subroutine expect(res, dd)
    type(results_t), intent(in) :: res
    real(wp), intent(in) :: dd             !! closed-form densification stroke
    real(wp) :: e
    e = energy(dmax)
    call check(res%valid, 'results valid')
    call check_close(res%stroke, dmax, 'stroke = the largest approach', rtol=1.0e-12_wp)
    call check_close(res%peak_force, force(dmax), 'peak force = F at the end', rtol=1.0e-12_wp)
    call check_close(res%absorbed_energy, e - 0.1_wp*e, 'absorbed = work - stored', rtol=1.0e-12_wp)
    call check_close(res%mean_force, 0.9_wp*e/dmax, 'mean force = absorbed / stroke', rtol=1.0e-12_wp)
    call check_close(res%cfe, 0.9_wp*e/dmax/force(dmax), 'cfe = mean / peak', rtol=1.0e-12_wp)
    call check_close(res%sea, 0.9_wp*e/2.5_wp, 'sea = absorbed / mass', rtol=1.0e-12_wp)
    ! the curve is sampled every 1e-5 m and its force averaged over +-1 % of the stroke
    call check(abs(res%densification_stroke - dd) <= 0.01_wp*dmax, &
               'densification stroke within 1 % of the stroke of the closed form')
    call check(dd > d1 .and. dd < dmax, 'the closed form densifies within the stroke')
  end subroutine expect

  subroutine case_one(mirror)
    logical, intent(in) :: mirror
    type(wall_t) :: walls(2)
    type(results_t) :: res
    integer :: st
    character(len=:), allocatable :: msg, path
    real(wp) :: e
    walls(1)%normal = [0.0_wp, -1.0_wp]
    walls(1)%velocity = [0.0_wp, -1.0_wp]
    walls(2)%normal = [0.0_wp, 1.0_wp]
    walls(2)%mirror = mirror              ! a quarter model's lower mirror plane, or a platen
    path = dir//'/history_one.csv'
    call write_history(path, 2, merge(0.5_wp, 1.0_wp, mirror))
    e = energy(dmax)
    call results_compute(path, walls, e, 0.1_wp*e, 2.5_wp, 1, res, st, msg)
    call check(st == 0, 'history read: '//msg)
    call check(res%loading_wall == 1, 'the moving platen loads, the other wall does not')
    call expect(res, densification())
    call check(res%supported .neqv. mirror, 'the fixed platen is a support, a mirror plane not')
    if (.not. mirror) then
      call check_close(res%support_peak_force, force(dmax), 'support peak = F at the end', &
                       rtol=1.0e-12_wp)
      call check_close(res%support_cfe, res%cfe, 'support cfe = cfe (one force through both)', &
                       rtol=1.0e-12_wp)
    end if
    call check(len(results_warning(res)) == 0, 'no spike, no warning: '//results_warning(res))
  end subroutine case_one

  !> case_one with the moving platen's force at 1e6 N on the first row after contact, 5.9 times
  !! the support's peak F(dmax) = 1.7e5 N: the peak and the CFE take it, the support's do not.
  subroutine case_spike()
    type(results_t) :: res
    integer :: st
    character(len=:), allocatable :: msg, path, w
    real(wp) :: e
    path = dir//'/history_spike.csv'
    call write_history(path, 2, 1.0_wp, spike=1.0e6_wp)
    e = energy(dmax)
    call results_compute(path, platens(), e, 0.1_wp*e, 2.5_wp, 1, res, st, msg)
    call check(st == 0, 'history read: '//msg)
    call check_close(res%peak_force, 1.0e6_wp, 'peak force = the spike', rtol=1.0e-12_wp)
    call check_close(res%support_peak_force, force(dmax), 'support peak = F at the end', &
                     rtol=1.0e-12_wp)
    call check_close(res%support_cfe, 0.9_wp*e/dmax/force(dmax), 'support cfe = mean / F(dmax)', &
                     rtol=1.0e-12_wp)
    w = results_warning(res)
    call check(index(w, 'peak_force is 5.88 x support_peak_force') > 0 .and. &
               index(w, 'support_cfe') > 0, &
               'the warning names the peak, its ratio to the support''s and what to use: '//w)
    call check(len('WARNING [results]: '//w) <= 120, 'the warning is one line of at most 120 '// &
               'characters: '//itoa(len('WARNING [results]: '//w)))
  end subroutine case_spike

  subroutine case_two()
    type(wall_t) :: walls(2)
    type(results_t) :: res
    integer :: st
    character(len=:), allocatable :: msg, path
    real(wp) :: e
    walls(1)%normal = [0.0_wp, -1.0_wp]
    walls(1)%velocity = [0.0_wp, -1.0_wp]
    walls(2)%normal = [0.0_wp, 1.0_wp]
    walls(2)%velocity = [0.0_wp, 1.0_wp]
    path = dir//'/history_two.csv'
    call write_history(path, 2, 0.5_wp)    ! each advances half the approach
    e = energy(dmax)
    call results_compute(path, walls, e, 0.1_wp*e, 2.5_wp, 1, res, st, msg)
    call check(st == 0, 'history read: '//msg)
    call check(res%n_loading == 2, 'both platens load')
    call check(.not. res%supported, 'no support: both platens move')
    call expect(res, densification())
  end subroutine case_two

  !> A drop test's curve: the plateau F0 to dmax, the force down to F0/100 over 4-7 % of the
  !! stroke (contact chatter), then unloading to zero over the last 5 % of the approach. E/F
  !! has its spurious maxima in the dip and on the unloading; the energy-efficiency method
  !! gives the stroke (no densification within it).
  subroutine case_dip()
    type(results_t) :: res
    integer :: st, i, n, nu
    character(len=:), allocatable :: msg, path
    real(wp), allocatable :: d(:), f(:)
    real(wp) :: e
    n = 4001
    nu = 201
    allocate(d(n + nu), f(n + nu))
    do i = 1, n + nu
      if (i <= n) then
        d(i) = dmax*real(i - 1, wp)/real(n - 1, wp)
        f(i) = merge(0.01_wp*f0, f0, d(i) > 0.04_wp*dmax .and. d(i) < 0.07_wp*dmax)
      else
        d(i) = dmax*(1.0_wp - 0.05_wp*real(i - n, wp)/real(nu, wp))
        f(i) = f0*(1.0_wp - real(i - n, wp)/real(nu, wp))
      end if
    end do
    path = dir//'/history_dip.csv'
    call write_curve(path, d, f, 0.0_wp*f, e)
    call results_compute(path, platens(), e, 0.0_wp, 2.5_wp, 1, res, st, msg)
    call check(st == 0, 'history read: '//msg)
    call check_close(res%stroke, dmax, 'stroke = the largest approach', rtol=1.0e-12_wp)
    call check(abs(res%densification_stroke - dmax) <= 0.01_wp*dmax, &
               'densification at the stroke: not in the dip, not on the unloading')
  end subroutine case_dip

  !> A square tube's curve: the force rises to 3 F0 over the first 2 % of the stroke, then
  !! falls linearly to F0 at dmax. E/F rises all along the fall (the force is below the mean
  !! force so far from about 0.1 dmax on): no maximum with the force rising beyond it, so no
  !! densification within the stroke (before, the edge of the points kept, about 0.1 dmax).
  subroutine case_soft()
    type(results_t) :: res
    integer :: st, i
    character(len=:), allocatable :: msg, path
    real(wp) :: d(4001), f(4001), e
    do i = 1, size(d)
      d(i) = dmax*real(i - 1, wp)/real(size(d) - 1, wp)
      f(i) = merge(3.0_wp*f0*d(i)/(0.02_wp*dmax), f0*(3.0_wp - 2.0_wp*(d(i) - 0.02_wp*dmax)/ &
        (0.98_wp*dmax)), d(i) < 0.02_wp*dmax)
    end do
    path = dir//'/history_soft.csv'
    call write_curve(path, d, f, f, e)
    call results_compute(path, platens(), e, 0.0_wp, 2.5_wp, 1, res, st, msg)
    call check(st == 0, 'history read: '//msg)
    call check_close(res%peak_force, 3.0_wp*f0, 'peak = the first peak', rtol=1.0e-12_wp)
    call check(abs(res%densification_stroke - dmax) <= 1.0e-12_wp*dmax, &
               'no densification: the stroke, not the edge of the points kept')
  end subroutine case_soft

  !> A moving platen (wall 1) above a fixed one (wall 2).
  function platens() result(walls)
    type(wall_t) :: walls(2)
    walls(1)%normal = [0.0_wp, -1.0_wp]
    walls(1)%velocity = [0.0_wp, -1.0_wp]
    walls(2)%normal = [0.0_wp, 1.0_wp]
  end function platens

  !> A history of platens(): wall 1 advancing d(:) under the force f(:), wall 2 reading fs(:);
  !! the plastic and external energy e, the trapezoidal work of the curve.
  subroutine write_curve(path, d, f, fs, e)
    character(len=*), intent(in) :: path
    real(wp), intent(in) :: d(:), f(:), fs(:)
    real(wp), intent(out) :: e
    integer :: u, i
    open(newunit=u, file=path, status='replace', action='write')
    write(u, '(a)') 'time,wall1_disp,wall1_force,wall1_fx,wall1_fy,wall2_disp,wall2_force,'// &
      'wall2_fx,wall2_fy,kinetic,strain,plastic,external'
    e = 0.0_wp
    do i = 1, size(d)
      e = e + 0.5_wp*(f(i) + f(max(i - 1, 1)))*(d(i) - d(max(i - 1, 1)))   ! (0 on the first)
      write(u, '(13(es24.16e3,:,","))') 1.0e-3_wp*real(i, wp), -d(i), f(i), 0.0_wp, f(i), &
        0.0_wp, fs(i), 0.0_wp, fs(i), 0.0_wp, 0.0_wp, e, e
    end do
    close(u)
  end subroutine write_curve

end program test_results
