!> A crush or a blow in the absorber engineer's terms (summary.nml `&results`, results.csv):
!! stroke, peak and mean force, crush force efficiency, absorbed energy, mass, specific energy
!! absorption, the densification stroke and each body's energy (docs/output.md, "Results").
!! SPDX-License-Identifier: MIT
!!
!! The loading walls are the walls that move into the material (not the mirror planes). Their
!! approach delta is the sum of their advances, each doubled where a mirror plane of a half or
!! quarter model lies parallel to it (the other half of the structure approaches from there).
!! The force-approach curve is read back from history.csv (the wall forces there are the mean
!! over each row's interval, as a load cell reports them), so a continued run gives the same
!! results as one run. The absorbed energy is the loading walls' exact work (accumulated every
!! step) less the elastic energy still stored at the end.
module mpm_results
  use mpm_kinds, only: wp
  use mpm_walls, only: wall_t
  use mpm_strings, only: itoa
  implicit none
  private
  public :: results_t, results_compute, results_write_group, results_write_csv, &
            loading_walls, results_warning

  !> The results of a run (for `depth`, the whole structure).
  type :: results_t
    logical :: valid = .false.             !! there is a loading wall and a curve
    integer :: n_loading = 0               !! loading walls
    integer :: loading_wall = 0            !! the first loading wall (input order)
    real(wp) :: stroke = 0.0_wp            !! largest approach delta [m]
    real(wp) :: peak_force = 0.0_wp        !! largest force on the loading walls [N]
    real(wp) :: mean_force = 0.0_wp        !! absorbed_energy / stroke [N]
    real(wp) :: cfe = 0.0_wp               !! mean_force / peak_force [-]
    real(wp) :: absorbed_energy = 0.0_wp   !! loading walls' work less stored elastic energy [J]
    real(wp) :: mass = 0.0_wp              !! the bodies' mass (unscaled) [kg]
    real(wp) :: sea = 0.0_wp               !! absorbed_energy / mass [J/kg]
    real(wp) :: densification_stroke = 0.0_wp  !! delta of the largest E(delta)/F(delta) [m]
    real(wp), allocatable :: body_energy(:)  !! each body's plastic dissipation [J]
    logical :: impactor = .false.          !! the loading wall is a wall with mass
    real(wp) :: impactor_rebound = 0.0_wp  !! its speed away from the material at the end [m/s]
    real(wp) :: impactor_max_stroke = 0.0_wp  !! its largest advance into the material [m]
    logical :: supported = .false.         !! a support faces the loading wall
    real(wp) :: support_peak_force = 0.0_wp  !! largest force on the supports [N]
    real(wp) :: support_cfe = 0.0_wp       !! mean_force / support_peak_force [-]
  end type results_t

contains

  !> Which walls load the material: not mirror planes, with a prescribed motion into it or a
  !! mass moving into it at the start.
  pure function loading_walls(walls) result(loading)
    type(wall_t), intent(in) :: walls(:)   !! the walls
    logical :: loading(size(walls))
    integer :: k
    do k = 1, size(walls)
      loading(k) = .not. walls(k)%mirror .and. &
                   (dot_product(walls(k)%velocity, walls(k)%normal) > 0.0_wp .or. &
                    walls(k)%mass > 0.0_wp .and. (walls(k)%travel_max > 0.0_wp .or. walls(k)%vn > 0.0_wp) .or. &
                    (walls(k)%n_motion > 0 .and. any(walls(k)%motion_f /= 0.0_wp) .and. &
                     dot_product(walls(k)%velocity, walls(k)%normal) /= 0.0_wp))
    end do
  end function loading_walls

  !> The factor on wall k's advance: 2 where a mirror plane lies parallel to it.
  pure real(wp) function approach_factor(walls, k) result(f)
    type(wall_t), intent(in) :: walls(:)   !! the walls
    integer, intent(in) :: k               !! a loading wall
    integer :: m
    f = 1.0_wp
    do m = 1, size(walls)
      if (walls(m)%mirror .and. abs(dot_product(walls(m)%normal, walls(k)%normal)) > 0.999_wp) &
        f = 2.0_wp
    end do
  end function approach_factor

  !> The results from history.csv (columns wall<k>_disp, wall<k>_force, plastic, strain and
  !! body<k>_plastic), the walls' accumulated work and the bodies' mass.
  subroutine results_compute(path, walls, work_full, strain_full, mass_full, nbody, res, &
                             stat, errmsg)
    character(len=*), intent(in) :: path   !! history.csv
    type(wall_t), intent(in) :: walls(:)   !! the walls (their motion; the mirror planes)
    real(wp), intent(in) :: work_full      !! the loading walls' work, whole structure [J]
    real(wp), intent(in) :: strain_full    !! stored elastic energy at the end, whole [J]
    real(wp), intent(in) :: mass_full      !! the bodies' unscaled mass, whole structure [kg]
    integer, intent(in) :: nbody           !! bodies
    type(results_t), intent(out) :: res    !! the results
    integer, intent(out) :: stat           !! 0, or non-zero: the file could not be read
    character(len=:), allocatable, intent(out) :: errmsg  !! the I/O problem
    real(wp), allocatable :: rows(:,:), delta(:), force(:), energy(:), support(:)
    integer, allocatable :: cdisp(:), cforce(:), cbody(:)
    logical :: loading(size(walls))
    real(wp) :: fac, w, da, dd
    integer :: k, i, n, ncol, cplastic
    errmsg = ''
    allocate(res%body_energy(nbody))
    res%body_energy = 0.0_wp
    res%mass = mass_full
    loading = loading_walls(walls)
    res%n_loading = count(loading)
    call read_history(path, rows, ncol, cdisp, cforce, cbody, cplastic, size(walls), nbody, &
                      stat, errmsg)
    if (stat /= 0) return
    n = size(rows, 2)
    if (cplastic > 0 .and. n > 0) then
      if (nbody > 1 .and. all(cbody > 0)) then
        res%body_energy = rows(cbody, n)
      else
        res%body_energy(1) = rows(cplastic, n)
      end if
    end if
    if (res%n_loading == 0 .or. n < 2 .or. any(cdisp(pack([(k, k = 1, size(walls))], loading)) == 0)) &
      return
    do k = 1, size(walls)
      if (loading(k)) then
        res%loading_wall = k
        exit
      end if
    end do
    if (walls(res%loading_wall)%mass > 0.0_wp) then
      res%impactor = .true.
      res%impactor_rebound = -walls(res%loading_wall)%vn
      res%impactor_max_stroke = walls(res%loading_wall)%travel_max
    end if
    allocate(delta(n), force(n), energy(n), support(n))
    ! the approach and the force on the loading walls (weighted by their share of the approach)
    delta = 0.0_wp
    force = 0.0_wp
    do k = 1, size(walls)
      if (.not. loading(k)) cycle
      fac = approach_factor(walls, k)
      delta = delta - fac*rows(cdisp(k), :)
    end do
    do i = 1, n
      do k = 1, size(walls)
        if (.not. loading(k)) cycle
        if (delta(i) > 0.0_wp) then
          w = -approach_factor(walls, k)*rows(cdisp(k), i)/delta(i)
        else
          w = 1.0_wp/real(res%n_loading, wp)
        end if
        force(i) = force(i) + w*rows(cforce(k), i)
      end do
    end do
    ! E(delta) along the rows (trapezoids over each wall's own advance)
    energy(1) = 0.0_wp
    do i = 2, n
      dd = 0.0_wp
      do k = 1, size(walls)
        if (.not. loading(k)) cycle
        da = -approach_factor(walls, k)*(rows(cdisp(k), i) - rows(cdisp(k), i - 1))
        dd = dd + 0.5_wp*(rows(cforce(k), i) + rows(cforce(k), i - 1))*da
      end do
      energy(i) = energy(i - 1) + dd
    end do
    res%stroke = maxval(delta)
    res%peak_force = maxval(force)
    ! the supports: the walls that face the first loading wall and do not move (a base, an
    ! anvil; not mirror planes), their forces summed as a load cell under them reads them
    support = 0.0_wp
    do k = 1, size(walls)
      if (loading(k) .or. walls(k)%mirror .or. dot_product(walls(k)%normal, &
          walls(res%loading_wall)%normal) > -0.999_wp) cycle
      res%supported = .true.
      support = support + rows(cforce(k), :)
    end do
    if (res%supported) res%support_peak_force = maxval(support)
    res%absorbed_energy = work_full - strain_full
    if (res%stroke > 0.0_wp) res%mean_force = res%absorbed_energy/res%stroke
    if (res%peak_force > 0.0_wp) res%cfe = res%mean_force/res%peak_force
    if (res%support_peak_force > 0.0_wp) res%support_cfe = res%mean_force/res%support_peak_force
    if (res%mass > 0.0_wp) res%sea = res%absorbed_energy/res%mass
    res%densification_stroke = densification_stroke(delta, force, energy, res%stroke)
    res%valid = res%stroke > 0.0_wp
  end subroutine results_compute

  !> The densification stroke: the largest energy efficiency E(delta)/F(delta), F averaged over
  !! +-1 % of the stroke so that the force noise of a row does not make the peak; on the loading
  !! branch only (up to the largest approach) and where the force is at least the mean force so
  !! far, E(delta)/delta: where contact chatter or unloading takes the force towards zero, E/F
  !! has spurious maxima. A maximum of E/F has dF/ddelta = F^2/E > 0: the force rises beyond it;
  !! a largest E/F where the force falls (a softening section, the edge of the points kept) is
  !! none, and the crush densifies at its stroke, as one that ends on its plateau.
  pure real(wp) function densification_stroke(delta, force, energy, stroke) result(dd)
    real(wp), intent(in) :: delta(:), force(:), energy(:)  !! the curve's rows
    real(wp), intent(in) :: stroke         !! the largest approach [m]
    real(wp), allocatable :: smooth(:)      ! (on the heap: a history may hold 1e6 rows)
    real(wp) :: window, best, eta
    integer :: i, j, j0, j1, imax, jbest
    allocate(smooth(size(delta)))
    window = 0.01_wp*stroke
    imax = maxloc(delta, dim=1)
    j0 = 1
    j1 = 1
    smooth = 0.0_wp
    do i = 1, imax
      do while (delta(j0) < delta(i) - window .and. j0 < i)
        j0 = j0 + 1
      end do
      j1 = max(j1, i)
      do while (j1 < imax)
        if (delta(j1 + 1) > delta(i) + window) exit
        j1 = j1 + 1
      end do
      smooth(i) = sum(force(j0:j1))/real(j1 - j0 + 1, wp)
    end do
    best = -1.0_wp
    jbest = 0
    do j = 1, imax
      if (.not. (delta(j) > 0.0_wp .and. smooth(j) > 0.0_wp)) cycle
      if (smooth(j)*delta(j) < energy(j)) cycle
      eta = energy(j)/smooth(j)
      if (eta > best) then
        best = eta
        jbest = j
      end if
    end do
    dd = stroke
    if (jbest == 0) return
    j = jbest
    do while (j < imax)
      if (delta(j) > delta(jbest) + 2.0_wp*window) exit
      j = j + 1
    end do
    if (smooth(j) > smooth(jbest)) dd = delta(jbest)
  end function densification_stroke

  !> history.csv as numbers (ncol, rows), and the columns named in its header.
  subroutine read_history(path, rows, ncol, cdisp, cforce, cbody, cplastic, nwall, nbody, &
                          stat, errmsg)
    character(len=*), intent(in) :: path
    real(wp), allocatable, intent(out) :: rows(:,:)
    integer, intent(out) :: ncol
    integer, allocatable, intent(out) :: cdisp(:), cforce(:), cbody(:)
    integer, intent(out) :: cplastic
    integer, intent(in) :: nwall, nbody
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    character(len=:), allocatable :: header, name
    character(len=512) :: msg
    character(len=65536) :: buf
    integer :: u, n, i0, i1, c, k, nrow
    allocate(cdisp(nwall), cforce(nwall), cbody(nbody))
    cdisp = 0; cforce = 0; cbody = 0; cplastic = 0; ncol = 0
    errmsg = ''
    open(newunit=u, file=path, status='old', action='read', iostat=stat, iomsg=msg)
    if (stat /= 0) then
      errmsg = 'cannot read '//trim(path)//': '//trim(msg)
      allocate(rows(0, 0))
      return
    end if
    read(u, '(a)', iostat=stat) buf
    header = trim(buf)
    ! the columns by name
    i0 = 1
    c = 0
    do
      i1 = index(header(i0:), ',')
      if (i1 == 0) then
        name = header(i0:)
      else
        name = header(i0:i0 + i1 - 2)
      end if
      c = c + 1
      do k = 1, nwall
        if (name == 'wall'//itoa(k)//'_disp') cdisp(k) = c
        if (name == 'wall'//itoa(k)//'_force') cforce(k) = c
      end do
      do k = 1, nbody
        if (name == 'body'//itoa(k)//'_plastic') cbody(k) = c
      end do
      if (name == 'plastic') cplastic = c
      if (i1 == 0) exit
      i0 = i0 + i1
    end do
    ncol = c
    nrow = 0
    do
      read(u, '(a)', iostat=stat) buf
      if (stat /= 0) exit
      if (len_trim(buf) > 0) nrow = nrow + 1
    end do
    rewind(u)
    read(u, '(a)', iostat=stat) buf
    allocate(rows(ncol, nrow))
    n = 0
    do while (n < nrow)
      read(u, '(a)', iostat=stat) buf
      if (stat /= 0) exit
      if (len_trim(buf) == 0) cycle
      n = n + 1
      read(buf, *, iostat=stat) rows(:, n)
      if (stat /= 0) then
        errmsg = 'cannot read row '//itoa(n)//' of '//trim(path)
        exit
      end if
    end do
    close(u)
    if (len(errmsg) == 0) stat = 0
  end subroutine read_history

  !> The group `&results` on unit u (summary.nml).
  subroutine results_write_group(u, res, stat, msg)
    integer, intent(in) :: u               !! open unit
    type(results_t), intent(in) :: res     !! the results
    integer, intent(out) :: stat           !! iostat
    character(len=*), intent(inout) :: msg !! iomsg
    integer :: k
    write(u, '(a)', iostat=stat, iomsg=msg) '&results'
    write(u, '(a,i0)', iostat=stat, iomsg=msg) '  loading_wall = ', res%loading_wall
    write(u, '(a,es24.16e3)', iostat=stat, iomsg=msg) '  stroke = ', res%stroke
    write(u, '(a,es24.16e3)', iostat=stat, iomsg=msg) '  peak_force = ', res%peak_force
    write(u, '(a,es24.16e3)', iostat=stat, iomsg=msg) '  mean_force = ', res%mean_force
    write(u, '(a,es24.16e3)', iostat=stat, iomsg=msg) '  cfe = ', res%cfe
    write(u, '(a,es24.16e3)', iostat=stat, iomsg=msg) '  absorbed_energy = ', res%absorbed_energy
    write(u, '(a,es24.16e3)', iostat=stat, iomsg=msg) '  mass = ', res%mass
    write(u, '(a,es24.16e3)', iostat=stat, iomsg=msg) '  sea = ', res%sea
    write(u, '(a,es24.16e3)', iostat=stat, iomsg=msg) '  densification_stroke = ', &
      res%densification_stroke
    do k = 1, size(res%body_energy)
      write(u, '(a,i0,a,es24.16e3)', iostat=stat, iomsg=msg) '  body', k, '_energy = ', &
        res%body_energy(k)
    end do
    if (res%impactor) then
      write(u, '(a,es24.16e3)', iostat=stat, iomsg=msg) '  impactor_rebound = ', &
        res%impactor_rebound
      write(u, '(a,es24.16e3)', iostat=stat, iomsg=msg) '  impactor_max_stroke = ', &
        res%impactor_max_stroke
    end if
    if (res%supported) then
      write(u, '(a,es24.16e3)', iostat=stat, iomsg=msg) '  support_peak_force = ', &
        res%support_peak_force
      write(u, '(a,es24.16e3)', iostat=stat, iomsg=msg) '  support_cfe = ', res%support_cfe
    end if
    write(u, '(a)', iostat=stat, iomsg=msg) '/'
  end subroutine results_write_group

  !> One line when the peak on the loading wall is more than twice the supports' (the inertia
  !! of the struck face: a rigid wall striking a flat face at speed v meets a stress of about
  !! rho c v until the wave has crossed the wall), else ''.
  function results_warning(res) result(text)
    type(results_t), intent(in) :: res     !! the results
    character(len=:), allocatable :: text
    character(len=12) :: ratio
    text = ''
    if (.not. (res%valid .and. res%supported .and. res%support_peak_force > 0.0_wp)) return
    if (.not. res%peak_force > 2.0_wp*res%support_peak_force) return
    write(ratio, '(g12.3)') res%peak_force/res%support_peak_force
    text = 'peak_force is '//trim(adjustl(ratio))//' x support_peak_force (impact '// &
      'inertia): use support_cfe (docs/output.md#results)'
  end function results_warning

  !> results.csv: one header line and one row (sweeps concatenate the rows).
  subroutine results_write_csv(path, title, res, stat, errmsg)
    character(len=*), intent(in) :: path   !! file path
    character(len=*), intent(in) :: title  !! the case's title
    type(results_t), intent(in) :: res     !! the results
    integer, intent(out) :: stat           !! 0 or iostat
    character(len=:), allocatable, intent(out) :: errmsg  !! the I/O problem
    character(len=512) :: msg
    character(len=:), allocatable :: head
    integer :: u, k
    errmsg = ''
    head = 'title,loading_wall,stroke,peak_force,mean_force,cfe,absorbed_energy,mass,sea,'// &
           'densification_stroke'
    do k = 1, size(res%body_energy)
      head = head//',body'//itoa(k)//'_energy'
    end do
    if (res%impactor) head = head//',impactor_rebound,impactor_max_stroke'
    if (res%supported) head = head//',support_peak_force,support_cfe'
    open(newunit=u, file=path, status='replace', action='write', iostat=stat, iomsg=msg)
    if (stat /= 0) then
      errmsg = 'cannot open '//trim(path)//' for writing: '//trim(msg)
      return
    end if
    write(u, '(a)', iostat=stat, iomsg=msg) head
    write(u, '(a,",",i0,*(:",",es24.16e3))', iostat=stat, iomsg=msg) trim(title), &
      res%loading_wall, res%stroke, res%peak_force, res%mean_force, res%cfe, &
      res%absorbed_energy, res%mass, res%sea, res%densification_stroke, res%body_energy, &
      pack([res%impactor_rebound, res%impactor_max_stroke], [res%impactor, res%impactor]), &
      pack([res%support_peak_force, res%support_cfe], [res%supported, res%supported])
    if (stat /= 0) errmsg = 'cannot write '//trim(path)//': '//trim(msg)
    close(u, iostat=stat, iomsg=msg)
    if (stat /= 0 .and. len(errmsg) == 0) errmsg = 'cannot close '//trim(path)//': '//trim(msg)
  end subroutine results_write_csv

end module mpm_results
