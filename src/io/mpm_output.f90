!> Text outputs of a run: history.csv rows and summary.nml (docs/output.md).
! SPDX-License-Identifier: MIT
!
! Forces, energies and masses are reported for `depth` and for the full structure: with a half
! or quarter ring, energies are multiplied by 2 or 4; a wall's force is summed with its images
! in the mirror planes that are perpendicular to it (the image of force f in a plane of normal m
! is f - 2 (f.m) m); the centre of mass of the full ring lies on the mirror planes.
module mpm_output
  use mpm_kinds, only: wp, i8
  use mpm_solver, only: sim_t
  use mpm_walls, only: wall_travel, wall_kinetic
  use mpm_results, only: results_t, results_write_group
  use mpm_material, only: material_energy_density
  use mpm_strings, only: itoa
  implicit none
  private
  public :: history_t, history_open, history_write, history_close, write_summary, full_force, &
            com_full, summary_t, next_output

  !> An open history file.
  type :: history_t
    integer :: unit = -1                   !! Fortran unit
    integer :: rows = 0                    !! rows written
    real(wp) :: next_time = 0.0_wp         !! time of the next row [s]
    real(wp) :: last_time = 0.0_wp         !! time of the last row [s]
    real(wp) :: every = 0.0_wp             !! interval [s] (0: every step)
    real(wp) :: depth = 1.0_wp             !! out-of-plane length [m]
    real(wp) :: factor = 1.0_wp            !! sector factor for energies and masses
    integer, allocatable :: probe(:)       !! particle index of each probe
  end type history_t

  !> What summary.nml reports.
  type :: summary_t
    character(len=16) :: status = 'completed'  !! completed | unstable | interrupted
    character(len=1024) :: message = ''        !! failure message, if any
    character(len=8) :: scene = ''             !! crush | wave | impact ('' : generic)
    real(wp) :: wall_seconds = 0.0_wp          !! elapsed wall-clock time [s]
    integer :: threads = 1                     !! OpenMP threads
  end type summary_t

contains

  !> The first output time after t on the grid next + k every [s]; an interval shorter than a
  !! step (more than 1000 of them in it), or below the round-off of t, gives the next step's.
  pure function next_output(next, every, t) result(tn)
    real(wp), intent(in) :: next           !! the output time just reached [s]
    real(wp), intent(in) :: every          !! the interval (> 0) [s]
    real(wp), intent(in) :: t              !! the time [s]
    real(wp) :: tn
    integer :: k
    tn = next
    do k = 1, 1000
      if (tn > t*(1.0_wp + 1.0e-12_wp)) return
      tn = tn + every
    end do
    if (tn <= t*(1.0_wp + 1.0e-12_wp)) tn = nearest(t*(1.0_wp + 1.0e-12_wp), 1.0_wp)
  end function next_output

  !> Create history.csv in dir and write the header line.
  subroutine history_open(h, path, s, every, depth, factor, probe, stat, errmsg, append)
    type(history_t), intent(out) :: h      !! the history file
    character(len=*), intent(in) :: path   !! file path
    type(sim_t), intent(in) :: s           !! simulation (walls)
    real(wp), intent(in) :: every          !! row interval [s]
    real(wp), intent(in) :: depth          !! out-of-plane length [m]
    real(wp), intent(in) :: factor         !! sector factor
    integer, intent(in) :: probe(:)        !! particle index of each probe
    integer, intent(out) :: stat           !! 0 or non-zero iostat
    character(len=:), allocatable, intent(out) :: errmsg  !! the I/O problem
    logical, intent(in), optional :: append  !! continue an existing file (restart)
    character(len=512) :: msg
    character(len=:), allocatable :: header
    integer :: k, i, j
    logical :: app
    app = .false.
    if (present(append)) app = append
    h%every = every
    h%depth = depth
    h%factor = factor
    h%probe = probe
    h%next_time = s%t
    h%last_time = s%t
    errmsg = ''
    if (app) then
      open(newunit=h%unit, file=path, status='old', position='append', action='write', &
           iostat=stat, iomsg=msg)
    else
      open(newunit=h%unit, file=path, status='replace', action='write', iostat=stat, iomsg=msg)
    end if
    if (stat /= 0) then
      errmsg = 'cannot open '//trim(path)//' for writing: '//trim(msg)
      return
    end if
    if (app) return
    header = 'time'
    do k = 1, s%nwall
      header = header//',wall'//itoa(k)//'_disp,wall'//itoa(k)//'_force,wall'//itoa(k)// &
               '_fx,wall'//itoa(k)//'_fy'
    end do
    header = header//',kinetic,strain,plastic,external,com_x,com_y,com_vx,com_vy'
    do k = 1, size(probe)
      header = header//',probe'//itoa(k)//'_x,probe'//itoa(k)//'_y,probe'//itoa(k)// &
               '_vx,probe'//itoa(k)//'_vy,probe'//itoa(k)//'_eqps'
    end do
    header = header//',damped,contact_loss,step,dt,energy_error'
    if (s%prm%nbody > 1) then                ! several bodies: per body, then per pair
      do k = 1, s%prm%nbody
        header = header//',body'//itoa(k)//'_x,body'//itoa(k)//'_y,body'//itoa(k)// &
          '_vx,body'//itoa(k)//'_vy,body'//itoa(k)//'_kinetic,body'//itoa(k)// &
          '_strain,body'//itoa(k)//'_plastic'
      end do
      do i = 1, s%prm%nbody - 1
        do j = i + 1, s%prm%nbody
          header = header//',contact'//itoa(i)//'_'//itoa(j)//'_force,contact'//itoa(i)// &
            '_'//itoa(j)//'_fx,contact'//itoa(i)//'_'//itoa(j)//'_fy'
        end do
      end do
    end if
    do k = 1, s%nwall                        ! a wall with mass: its motion
      if (s%walls(k)%mass > 0.0_wp) header = header//',wall'//itoa(k)//'_velocity,wall'// &
        itoa(k)//'_kinetic'
    end do
    write(h%unit, '(a)', iostat=stat, iomsg=msg) header
    if (stat /= 0) errmsg = 'cannot write '//trim(path)//': '//trim(msg)
  end subroutine history_open

  !> Write a row if the interval has passed (or force); flushes every row. Wall forces are the
  !! mean over the time since the previous row (impulse / time), as a load cell reports them;
  !! with history_every = 0 that is the force of the last step.
  subroutine history_write(h, s, force, stat, errmsg)
    type(history_t), intent(inout) :: h    !! the history file
    type(sim_t), intent(inout) :: s        !! simulation (the walls' impulse sums are reset)
    logical, intent(in) :: force           !! write regardless of the interval
    integer, intent(out) :: stat           !! 0 or iostat
    character(len=:), allocatable, intent(out) :: errmsg  !! the I/O problem
    real(wp) :: row(4*s%nwall + 14 + 5*size(h%probe) + &
                    merge(7*s%prm%nbody + 3*s%prm%npair, 0, s%prm%nbody > 1) + &
                    2*count(s%walls(1:s%nwall)%mass > 0.0_wp)), f(2), c(2), cv(2)
    integer :: k, i, ip
    character(len=512) :: msg
    stat = 0
    errmsg = ''
    if (.not. force .and. s%t < h%next_time*(1.0_wp - 1.0e-12_wp)) return
    if (h%every > 0.0_wp) h%next_time = next_output(h%next_time, h%every, s%t)
    row(1) = s%t
    i = 1
    do k = 1, s%nwall
      if (s%t > h%last_time) then
        f = -s%walls(k)%impulse_acc/(s%t - h%last_time)
      else
        f = s%walls(k)%force
      end if
      s%walls(k)%impulse_acc = 0.0_wp
      f = full_force(s, k, f)*h%depth
      row(i + 1) = wall_travel(s%walls(k), s%t)
      row(i + 2) = -dot_product(f, s%walls(k)%normal)
      row(i + 3:i + 4) = f
      i = i + 4
    end do
    row(i + 1) = s%e_kin*h%depth*h%factor
    row(i + 2) = (s%e_strain + s%e_contact)*h%depth*h%factor   ! with the walls' contact
    row(i + 3) = s%e_plastic*h%depth*h%factor
    row(i + 4) = s%e_external*h%depth*h%factor
    call com_full(s, c, cv)
    row(i + 5:i + 6) = c
    row(i + 7:i + 8) = cv
    i = i + 8
    do k = 1, size(h%probe)
      ip = h%probe(k)
      row(i + 1:i + 2) = s%p%x(:, ip)
      row(i + 3:i + 4) = s%p%v(:, ip)
      row(i + 5) = s%p%eqps(ip)
      i = i + 5
    end do
    row(i + 1) = s%e_damped*h%depth*h%factor
    row(i + 2) = s%e_contact_loss*h%depth*h%factor
    row(i + 3) = real(s%step, wp)
    row(i + 4) = s%dt
    row(i + 5) = s%energy_error
    i = i + 5
    if (s%prm%nbody > 1) then
      call body_columns(h, s, row(i + 1:))
      i = i + 7*s%prm%nbody + 3*s%prm%npair
    end if
    do k = 1, s%nwall
      if (.not. s%walls(k)%mass > 0.0_wp) cycle
      row(i + 1) = -s%walls(k)%vn                ! along minus the normal, as wall<k>_disp
      row(i + 2) = wall_kinetic(s%walls(k))*h%depth*h%factor
      i = i + 2
    end do
    row = row + 0.0_wp                     ! no negative zeros in the file
    write(h%unit, '(es24.16e3,*(:",",es24.16e3))', iostat=stat, iomsg=msg) row
    if (stat /= 0) then
      errmsg = 'cannot write a history row: '//trim(msg)
      return
    end if
    flush(h%unit, iostat=stat, iomsg=msg)
    h%rows = h%rows + 1
    h%last_time = s%t
  end subroutine history_write

  !> The columns of several bodies: per body its centre of mass and velocity (of the full
  !! structure), kinetic, stored elastic and plastic energy; per pair of bodies i < j the
  !! normal force between them and the force on body i, the mean since the previous row (the
  !! pair's impulse sums are reset), summed with its images in the mirror planes.
  subroutine body_columns(h, s, row)
    type(history_t), intent(in) :: h       !! the history file (last row time, depth, factor)
    type(sim_t), intent(inout) :: s        !! simulation (the pairs' sums are reset)
    real(wp), intent(out) :: row(:)        !! 7 per body, then 3 per pair
    real(wp) :: m(s%prm%nbody), mx(2, s%prm%nbody), mv(2, s%prm%nbody), e(3, s%prm%nbody)
    real(wp) :: f(3), c(2), cv(2), mn(2)
    integer :: ip, k, j, ib
    m = 0.0_wp
    mx = 0.0_wp
    mv = 0.0_wp
    e = 0.0_wp
    do ip = 1, s%p%np
      ib = s%p%body(ip)
      m(ib) = m(ib) + s%p%mass(ip)
      mx(:, ib) = mx(:, ib) + s%p%mass(ip)*s%p%x(:, ip)
      mv(:, ib) = mv(:, ib) + s%p%mass(ip)*s%p%v(:, ip)
      e(1, ib) = e(1, ib) + 0.5_wp*s%p%mass(ip)*dot_product(s%p%v(:, ip), s%p%v(:, ip))
      e(2, ib) = e(2, ib) + s%p%vol(ip)*material_energy_density(s%prm%mats(s%p%mat(ip)), &
                 s%prm%plane, s%p%stress(:, ip), s%p%F(:, :, ip))
      e(3, ib) = e(3, ib) + s%p%wplastic(ip)
    end do
    do k = 1, s%prm%nbody
      c = mx(:, k)/m(k)
      cv = mv(:, k)/m(k)
      do j = 1, s%nwall                      ! the full body's centre lies on the planes
        if (.not. s%walls(j)%mirror) cycle
        mn = s%walls(j)%normal
        c = c - dot_product(c - s%walls(j)%point, mn)*mn
        cv = cv - dot_product(cv, mn)*mn
      end do
      row(7*k - 6:7*k - 5) = c
      row(7*k - 4:7*k - 3) = cv
      row(7*k - 2:7*k) = e(:, k)*h%depth*h%factor
    end do
    do k = 1, s%prm%npair
      if (s%t > h%last_time) then
        f = s%pair_acc(:, k)/(s%t - h%last_time)
      else
        f = s%pair_force(:, k)
      end if
      s%pair_acc(:, k) = 0.0_wp
      do j = 1, s%nwall                      ! with the images in the mirror planes
        if (.not. s%walls(j)%mirror) cycle
        mn = s%walls(j)%normal
        f(1) = 2.0_wp*f(1)
        f(2:3) = 2.0_wp*f(2:3) - 2.0_wp*dot_product(f(2:3), mn)*mn
      end do
      row(7*s%prm%nbody + 3*k - 2:7*s%prm%nbody + 3*k) = f*h%depth
    end do
  end subroutine body_columns

  !> Close the history file.
  subroutine history_close(h)
    type(history_t), intent(inout) :: h    !! the history file
    integer :: ios
    logical :: op
    op = .false.
    if (h%unit /= -1) inquire(unit=h%unit, opened=op)   ! (newunit numbers are negative)
    if (op) close(h%unit, iostat=ios)
    h%unit = -1
  end subroutine history_close

  !> Force of the full structure on wall k: f summed with its images in the mirror planes
  !! perpendicular to the wall [N/m].
  pure function full_force(s, k, f) result(ff)
    type(sim_t), intent(in) :: s           !! simulation
    integer, intent(in) :: k               !! wall index
    real(wp), intent(in) :: f(2)           !! force of the modelled part [N/m]
    real(wp) :: ff(2), m(2)
    integer :: j
    ff = f
    do j = 1, s%nwall
      if (j == k .or. .not. s%walls(j)%mirror) cycle
      m = s%walls(j)%normal
      if (abs(dot_product(m, s%walls(k)%normal)) < 1.0e-6_wp) then
        ff = 2.0_wp*ff - 2.0_wp*dot_product(ff, m)*m
      end if
    end do
  end function full_force

  !> Centre of mass and its velocity of the full structure [m, m/s].
  pure subroutine com_full(s, c, cv)
    type(sim_t), intent(in) :: s           !! simulation
    real(wp), intent(out) :: c(2)          !! centre of mass [m]
    real(wp), intent(out) :: cv(2)         !! its velocity [m/s]
    real(wp) :: mtot, m(2)
    integer :: ip, j
    mtot = 0.0_wp
    c = 0.0_wp
    cv = 0.0_wp
    do ip = 1, s%p%np
      mtot = mtot + s%p%mass(ip)
      c = c + s%p%mass(ip)*s%p%x(:, ip)
      cv = cv + s%p%mass(ip)*s%p%v(:, ip)
    end do
    c = c/mtot
    cv = cv/mtot
    do j = 1, s%nwall
      if (.not. s%walls(j)%mirror) cycle
      m = s%walls(j)%normal
      c = c - dot_product(c - s%walls(j)%point, m)*m
      cv = cv - dot_product(cv, m)*m
    end do
  end subroutine com_full

  !> Write summary.nml (group &summary).
  subroutine write_summary(path, s, sm, stat, errmsg, res)
    character(len=*), intent(in) :: path   !! file path
    type(sim_t), intent(in) :: s           !! simulation
    type(summary_t), intent(in) :: sm      !! run figures
    type(results_t), intent(in), optional :: res  !! &results, written when valid
    integer, intent(out) :: stat           !! 0 or iostat
    character(len=:), allocatable, intent(out) :: errmsg  !! the I/O problem
    integer :: u
    character(len=512) :: msg
    real(wp) :: ratio, ups
    errmsg = ''
    ratio = s%t/max(sm%wall_seconds, 1.0e-9_wp)
    ups = real(s%p%np, wp)*real(s%step, wp)/max(sm%wall_seconds, 1.0e-9_wp)
    open(newunit=u, file=path, status='replace', action='write', iostat=stat, iomsg=msg)
    if (stat /= 0) then
      errmsg = 'cannot open '//trim(path)//' for writing: '//trim(msg)
      return
    end if
    write(u, '(a)', iostat=stat, iomsg=msg) '&summary'
    write(u, '(3a)', iostat=stat, iomsg=msg) '  status = ''', trim(sm%status), ''''
    write(u, '(3a)', iostat=stat, iomsg=msg) '  scene = ''', &
      trim(merge(sm%scene, 'generic ', len_trim(sm%scene) > 0)), ''''
    write(u, '(a,i0)', iostat=stat, iomsg=msg) '  steps = ', s%step
    write(u, '(a,i0)', iostat=stat, iomsg=msg) '  particles = ', s%p%np
    write(u, '(a,i0)', iostat=stat, iomsg=msg) '  nodes = ', s%g%nn
    write(u, '(a,es24.16e3)', iostat=stat, iomsg=msg) '  sim_time = ', s%t
    write(u, '(a,es24.16e3)', iostat=stat, iomsg=msg) '  wall_seconds = ', sm%wall_seconds
    write(u, '(a,es24.16e3)', iostat=stat, iomsg=msg) '  runtime_ratio = ', ratio
    write(u, '(a,es24.16e3)', iostat=stat, iomsg=msg) '  updates_per_second = ', ups
    write(u, '(a,i0)', iostat=stat, iomsg=msg) '  threads = ', sm%threads
    write(u, '(a,es24.16e3)', iostat=stat, iomsg=msg) '  energy_error = ', s%energy_error
    write(u, '(a,es24.16e3)', iostat=stat, iomsg=msg) '  dt_last = ', s%dt
    write(u, '(a,i0)', iostat=stat, iomsg=msg) '  active_nodes = ', s%g%nactive
    write(u, '(a,i0)', iostat=stat, iomsg=msg) '  grid_grown = ', s%diag%grown
    write(u, '(a,es24.16e3)', iostat=stat, iomsg=msg) '  min_corner_jacobian = ', s%diag%jmin_seen
    write(u, '(a,es24.16e3)', iostat=stat, iomsg=msg) '  max_area_deviation = ', s%diag%area_dev
    write(u, '(3a)', iostat=stat, iomsg=msg) '  message = ''', &
      trim(quote_free(sm%message)), ''''
    write(u, '(a)', iostat=stat, iomsg=msg) '/'
    if (present(res) .and. stat == 0) then
      if (res%valid) call results_write_group(u, res, stat, msg)
    end if
    if (stat /= 0) errmsg = 'cannot write '//trim(path)//': '//trim(msg)
    close(u, iostat=stat, iomsg=msg)
    if (stat /= 0 .and. len(errmsg) == 0) errmsg = 'cannot close '//trim(path)//': '//trim(msg)
  end subroutine write_summary

  !> The text with single quotes doubled (namelist string).
  pure function quote_free(text) result(out)
    character(len=*), intent(in) :: text   !! text
    character(len=:), allocatable :: out
    integer :: i
    out = ''
    do i = 1, len_trim(text)
      out = out//text(i:i)
      if (text(i:i) == '''') out = out//''''
    end do
  end function quote_free

end module mpm_output
