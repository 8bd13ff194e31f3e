!> The simulation state and one explicit MPM time step (METHOD.md sec. 2).
! SPDX-License-Identifier: MIT
!
! One step, as numbered in docs/algorithm.md:
!   1. basis: node block, weights and gradients of every particle (once per step, reused)
!   2. P2G: mass, momentum, internal and body forces (USF: stress update first)
!   3. grid update, damping, walls (reaction = momentum removed / dt)
!   4. G2P: FLIP/PIC velocity blend, positions
!   5. MUSL: momenta mapped back to the grid, walls re-applied
!   6. deformation: L, F, volume, stress; CPDI domains (corners / half-vectors)
!   7. energies and health checks
! Everything is per unit depth inside; outputs scale by depth (and the sector factor).
module mpm_solver
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use mpm_kinds, only: wp, i8
  use mpm_constants, only: msg_len, EXIT_NUMERIC, BASIS_LINEAR, BASIS_UGIMP, BASIS_CPDI1, &
                           BASIS_CPDI2, SCHEME_USL, SCHEME_USF, SCHEME_MUSL, CONTACT_SLIP
  use mpm_particles, only: particles_t, quad_area_centroid
  use mpm_grid, only: grid_t, grid_grow
  use mpm_walls, only: wall_t, wall_velocity, wall_constrain_node, wall_travel
  use mpm_material, only: material_t, material_stress_update, material_energy_density
  use mpm_basis, only: weights_linear, weights_ugimp, weights_cpdi1, weights_cpdi2, cpdi2_geometry, &
                       bilinear_at
  use mpm_strings, only: itoa, rtoa
  implicit none
  private
  public :: sim_t, solver_step, solver_stable_dt, solver_energies, solver_wall_point, &
            solver_init_energy

  !> Everything that evolves, plus the parameters of the step.
  type :: sim_t
    type(particles_t) :: p                 !! particles
    type(grid_t) :: g                      !! grid
    type(wall_t), allocatable :: walls(:)  !! rigid walls
    type(material_t), allocatable :: mats(:)  !! materials
    integer :: nwall = 0                   !! number of walls
    integer :: basis = BASIS_CPDI2         !! BASIS_* code
    integer :: scheme = SCHEME_MUSL        !! SCHEME_* code
    integer :: plane = 1                   !! PLANE_* code
    real(wp) :: flip = 1.0_wp              !! FLIP fraction [-]
    real(wp) :: damping = 0.0_wp           !! mass-proportional damping [1/s]
    real(wp) :: cfl = 0.2_wp               !! Courant number [-]
    real(wp) :: dt_fixed = 0.0_wp          !! fixed time step if > 0 [s]
    real(wp) :: t_end = 0.0_wp             !! end time [s]
    real(wp) :: gravity(2) = 0.0_wp        !! body acceleration [m/s^2]
    real(wp) :: c_max = 0.0_wp             !! largest dilatational wave speed [m/s]
    real(wp) :: energy_tol = 0.2_wp        !! energy growth that counts as blow-up [-]
    ! time
    real(wp) :: t = 0.0_wp                 !! time [s]
    real(wp) :: dt = 0.0_wp                !! last time step [s]
    integer(i8) :: step = 0_i8             !! steps done
    real(wp) :: vmax = 0.0_wp              !! largest particle speed [m/s]
    ! per-step basis cache
    integer :: nb = 0                      !! block width (nodes per direction)
    integer, allocatable :: blk(:,:)       !! lower-left node of each block (2, np)
    real(wp), allocatable :: w(:,:)        !! weights (nb*nb, np)
    real(wp), allocatable :: gw(:,:,:)     !! gradients (2, nb*nb, np) [1/m]
    real(wp), allocatable :: bacc(:,:)     !! optional per-particle body acceleration [m/s^2]
    ! energies per unit depth of the modelled part [J/m]
    real(wp) :: e_kin = 0.0_wp, e_strain = 0.0_wp, e_plastic = 0.0_wp
    real(wp) :: e_external = 0.0_wp, e_damped = 0.0_wp, e0 = 0.0_wp
    real(wp) :: w_gravity = 0.0_wp         !! work of gravity and body forces [J/m]
    real(wp) :: energy_error = 0.0_wp      !! largest relative energy error so far [-]
    real(wp) :: jmin_seen = 1.0_wp         !! smallest CPDI2 corner Jacobian ratio seen [-]
    real(wp) :: area_dev = 0.0_wp          !! largest |shoelace area / (J V0) - 1| seen [-]
    integer :: grown = 0                   !! times the grid was enlarged
  end type sim_t

contains

  !> Stable time step cfl * h / (c_d + max particle speed) [s] (METHOD.md sec. 2).
  pure function solver_stable_dt(s) result(dt)
    type(sim_t), intent(in) :: s           !! simulation
    real(wp) :: dt
    dt = s%cfl*s%g%h/(s%c_max + s%vmax)
  end function solver_stable_dt

  !> Current point on wall k [m].
  pure function solver_wall_point(s, k) result(x)
    type(sim_t), intent(in) :: s           !! simulation
    integer, intent(in) :: k               !! wall index
    real(wp) :: x(2)
    x = s%walls(k)%point0 - wall_travel(s%walls(k), s%t)*s%walls(k)%normal
    ! wall_travel is the travel along -normal; the tangential part of the motion does not move
    ! the plane, so point0 + travel*(-normal) is a point on the current plane.
  end function solver_wall_point

  !> Kinetic and stored elastic energy of the particles now [J/m].
  subroutine solver_energies(s, ekin, estrain)
    type(sim_t), intent(in) :: s           !! simulation
    real(wp), intent(out) :: ekin          !! kinetic energy [J/m]
    real(wp), intent(out) :: estrain       !! stored elastic energy [J/m]
    integer :: ip
    ekin = 0.0_wp
    estrain = 0.0_wp
    do ip = 1, s%p%np
      ekin = ekin + 0.5_wp*s%p%mass(ip)*dot_product(s%p%v(:, ip), s%p%v(:, ip))
      estrain = estrain + s%p%vol(ip)*material_energy_density(s%mats(s%p%mat(ip)), s%plane, &
                s%p%stress(:, ip), s%p%F(:, :, ip))
    end do
  end subroutine solver_energies

  !> Set the energies and E0 from the initial state.
  subroutine solver_init_energy(s)
    type(sim_t), intent(inout) :: s        !! simulation
    integer :: ip
    call solver_energies(s, s%e_kin, s%e_strain)
    s%e0 = s%e_kin + s%e_strain
    s%vmax = 0.0_wp
    do ip = 1, s%p%np
      s%vmax = max(s%vmax, sqrt(dot_product(s%p%v(:, ip), s%p%v(:, ip))))
    end do
  end subroutine solver_init_energy

  !> Advance by one time step (clipped to end exactly at t_end).
  !! stat = EXIT_NUMERIC with a message naming what failed, where and the remedy.
  subroutine solver_step(s, stat, errmsg)
    type(sim_t), intent(inout) :: s        !! simulation
    integer, intent(out) :: stat           !! 0 or EXIT_NUMERIC
    character(len=:), allocatable, intent(out) :: errmsg  !! what failed
    real(wp) :: dt, emech, scale, excess
    integer :: k
    stat = 0
    errmsg = ''
    ! time step
    if (s%dt_fixed > 0.0_wp) then
      dt = s%dt_fixed
    else
      dt = solver_stable_dt(s)
    end if
    if (s%t + 1.0001_wp*dt >= s%t_end) dt = s%t_end - s%t
    if (.not. dt > 0.0_wp) then
      stat = EXIT_NUMERIC
      errmsg = 'time step '//rtoa(dt)//' s is not positive at t = '//rtoa(s%t)// &
               ' s: particle speeds are not finite; lower cfl'
      return
    end if
    s%dt = dt
    do k = 1, s%nwall
      s%walls(k)%point = solver_wall_point(s, k)
      s%walls(k)%impulse = 0.0_wp
    end do

    ! 1. basis: weights and gradients once per step, reused by every transfer
    call compute_basis(s, stat, errmsg)
    if (stat /= 0) return
    ! 2. P2G (USF: stress first, from the velocity mapped at the start of the step)
    call p2g(s, with_force=.false.)
    if (s%scheme == SCHEME_USF) then
      call grid_velocity_from_momentum(s)
      call apply_walls(s, dt, record=.false.)
      call update_deformation(s, dt, stat, errmsg)
      if (stat /= 0) return
    end if
    call p2g(s, with_force=.true.)
    ! 3. grid update, damping and walls
    call grid_update(s, dt)
    call apply_walls(s, dt, record=.true.)
    ! 4. G2P
    call g2p(s, dt)
    ! 5. MUSL: map the new particle momenta back to the grid, re-apply the walls
    if (s%scheme == SCHEME_MUSL) then
      call p2g(s, with_force=.false.)
      call grid_velocity_from_momentum(s)
      call apply_walls(s, dt, record=.false.)
    end if
    ! 6. deformation and stress (USF did it in step 2), then the particle domains
    if (s%scheme /= SCHEME_USF) then
      call update_deformation(s, dt, stat, errmsg)
      if (stat /= 0) return
    end if
    call update_domains(s, dt)

    ! 7. time, wall forces and work, energy balance
    s%t = s%t + dt
    s%step = s%step + 1_i8
    do k = 1, s%nwall
      s%walls(k)%force = -s%walls(k)%impulse/dt
      s%walls(k)%impulse_acc = s%walls(k)%impulse_acc + s%walls(k)%impulse
      s%walls(k)%work = s%walls(k)%work + dot_product(s%walls(k)%impulse, &
                        wall_velocity(s%walls(k), s%t - 0.5_wp*dt))
    end do
    s%e_external = s%w_gravity
    do k = 1, s%nwall
      s%e_external = s%e_external + s%walls(k)%work
    end do
    emech = s%e_kin + s%e_strain + s%e_plastic + s%e_damped
    scale = max(s%e0, abs(s%e_external), tiny(1.0_wp))
    excess = emech - s%e_external - s%e0
    s%energy_error = max(s%energy_error, abs(excess)/scale)
    if (excess > s%energy_tol*scale .and. s%step > 10_i8) then
      stat = EXIT_NUMERIC
      errmsg = 'energy blow-up at step '//itoa(s%step)//', t = '//rtoa(s%t)// &
        ' s: kinetic + elastic + plastic + damped energy exceeds the initial energy plus the '// &
        'work put in by '//rtoa(100.0_wp*excess/scale)//' %. The time step dt = '//rtoa(dt)// &
        ' s (cfl = '//rtoa(dt*(s%c_max + s%vmax)/s%g%h)//') is probably above the '// &
        'stable limit: lower cfl (0.1 to 0.3) or dt'
      return
    end if
  end subroutine solver_step

  !> Step 1: block, weights and gradients of every particle; grows the block width and the
  !! grid as needed; detects folded CPDI2 domains and particles leaving a fixed grid.
  subroutine compute_basis(s, stat, errmsg)
    type(sim_t), intent(inout) :: s        !! simulation
    integer, intent(out) :: stat           !! 0 or EXIT_NUMERIC
    character(len=:), allocatable, intent(out) :: errmsg  !! what failed
    integer :: ip, need, need_max, lo(2), hi(2), add(4), bad, attempt, nb, nx, ny
    real(wp) :: origin(2), h, xq(2, 4), area, cen(2), jmin, jmin_all
    stat = 0
    errmsg = ''
    if (s%nb == 0) then
      select case (s%basis)
      case (BASIS_LINEAR); s%nb = 2
      case default; s%nb = 3
      end select
      call allocate_cache(s)
    end if
    do attempt = 1, 8
      origin = s%g%origin
      h = s%g%h
      nb = s%nb
      nx = s%g%nx
      ny = s%g%ny
      need_max = 0
      lo = huge(1)
      hi = -huge(1)
      jmin_all = huge(1.0_wp)
      bad = 0
      !$omp parallel do default(none) schedule(static) &
      !$omp   shared(s, origin, h, nb) private(ip, need, xq, area, cen, jmin) &
      !$omp   reduction(max: need_max, bad) reduction(min: lo, jmin_all) reduction(max: hi)
      do ip = 1, s%p%np
        select case (s%basis)
        case (BASIS_LINEAR)
          call weights_linear(s%p%x(:, ip), origin, h, nb, s%blk(1, ip), s%blk(2, ip), &
                            s%w(:, ip), s%gw(:, :, ip), need)
        case (BASIS_UGIMP)
          call weights_ugimp(s%p%x(:, ip), s%p%half(:, ip), origin, h, nb, s%blk(1, ip), &
                           s%blk(2, ip), s%w(:, ip), s%gw(:, :, ip), need)
        case (BASIS_CPDI1)
          call weights_cpdi1(s%p%x(:, ip), matmul(s%p%F(:, :, ip), s%p%r10(:, ip)), &
                           matmul(s%p%F(:, :, ip), s%p%r20(:, ip)), origin, h, nb, &
                           s%blk(1, ip), s%blk(2, ip), s%w(:, ip), s%gw(:, :, ip), need)
        case default
          xq(:, 1) = s%p%xc(:, s%p%corner(1, ip))
          xq(:, 2) = s%p%xc(:, s%p%corner(2, ip))
          xq(:, 3) = s%p%xc(:, s%p%corner(3, ip))
          xq(:, 4) = s%p%xc(:, s%p%corner(4, ip))
          call cpdi2_geometry(xq, area, cen, jmin)
          if (.not. jmin > 0.0_wp) bad = max(bad, ip)
          jmin_all = min(jmin_all, jmin)
          call weights_cpdi2(xq, origin, h, nb, s%blk(1, ip), s%blk(2, ip), s%w(:, ip), &
                           s%gw(:, :, ip), need)
        end select
        need_max = max(need_max, need)
        lo = min(lo, s%blk(:, ip))
        hi = max(hi, s%blk(:, ip) + need - 1)
      end do
      !$omp end parallel do
      if (s%basis == BASIS_CPDI2) s%jmin_seen = min(s%jmin_seen, jmin_all)
      if (bad > 0) then
        stat = EXIT_NUMERIC
        errmsg = 'CPDI2 domain of particle '//itoa(bad)//' at ('//rtoa(s%p%x(1, bad))//', '// &
          rtoa(s%p%x(2, bad))//') m folded or inverted at step '//itoa(s%step)//', t = '// &
          rtoa(s%t)//' s (corner Jacobian <= 0). Remedy: more particles through the wall '// &
          '(n_thick), a smaller cfl, or basis = ''cpdi1'' / ''ugimp'' for very deep crushes'
        return
      end if
      if (need_max > s%nb) then          ! domains grew: widen the blocks and redo
        s%nb = need_max
        call allocate_cache(s)
        cycle
      end if
      if (all(lo >= 0) .and. hi(1) <= nx - 1 .and. hi(2) <= ny - 1) return
      if (s%g%fixed) then
        bad = 0
        do ip = 1, s%p%np
          if (any(s%blk(:, ip) < 0) .or. s%blk(1, ip) + s%nb - 1 > nx - 1 .or. &
              s%blk(2, ip) + s%nb - 1 > ny - 1) then
            bad = ip
            exit
          end if
        end do
        bad = max(bad, 1)
        stat = EXIT_NUMERIC
        errmsg = 'particle '//itoa(bad)//' at ('//rtoa(s%p%x(1, bad))//', '// &
          rtoa(s%p%x(2, bad))//') m left the grid at step '//itoa(s%step)//', t = '// &
          rtoa(s%t)//' s. Remedy: enlarge &grid lower/upper, or omit them so that the '// &
          'grid is fitted and grows with the material'
        return
      end if
      ! enlarge the grid by what is missing plus a margin (the grid holds no state)
      add(1) = max(0, -lo(1)); add(2) = max(0, -lo(2))
      add(3) = max(0, hi(1) - (nx - 1)); add(4) = max(0, hi(2) - (ny - 1))
      where (add > 0) add = add + 2 + max(nx, ny)/10
      call grid_grow(s%g, add, s%nwall)
      s%grown = s%grown + 1
    end do
    stat = EXIT_NUMERIC
    errmsg = 'could not fit the grid to the particles at step '//itoa(s%step)// &
             ': positions are probably not finite; lower cfl'
  end subroutine compute_basis

  !> (Re)allocate the per-step basis cache for the current block width.
  subroutine allocate_cache(s)
    type(sim_t), intent(inout) :: s        !! simulation
    if (allocated(s%w)) deallocate(s%w, s%gw, s%blk)
    allocate(s%blk(2, s%p%np), s%w(s%nb*s%nb, s%p%np), s%gw(2, s%nb*s%nb, s%p%np))
  end subroutine allocate_cache

  !> Step 2 / 5: P2G of mass and momentum, and with_force the internal and body forces.
  subroutine p2g(s, with_force)
    type(sim_t), intent(inout) :: s        !! simulation
    logical, intent(in) :: with_force      !! also map forces
    integer :: n, k
    real(wp) :: mmax, cutoff
    if (with_force) then
      call p2g_force_kernel(s%p%np, s%nb, s%g%nx, s%blk, s%w, s%gw, s%p%mass, s%p%vol, &
                            s%p%stress, s%gravity, allocated(s%bacc), s%bacc, s%g%force)
      return
    end if
    call p2g_mass_kernel(s%p%np, s%nb, s%g%nx, s%blk, s%w, s%p%mass, s%p%v, s%g%mass, s%g%mom)
    ! active nodes: those with mass above the cut-off (METHOD.md sec. 2)
    mmax = maxval(s%g%mass)
    cutoff = 1.0e-12_wp*mmax
    k = 0
    do n = 1, s%g%nn
      if (s%g%mass(n) > cutoff) then
        k = k + 1
        s%g%active(k) = n
      end if
    end do
    s%g%nactive = k
  end subroutine p2g

  !> Mass and momentum scatter with an array reduction over threads.
  subroutine p2g_mass_kernel(np, nb, nx, blk, w, mass, v, gmass, gmom)
    integer, intent(in) :: np, nb, nx      !! particles, block width, nodes along x
    integer, intent(in) :: blk(:,:)        !! block origins (2, np)
    real(wp), intent(in) :: w(:,:)         !! weights (nb*nb, np)
    real(wp), intent(in) :: mass(:)        !! particle mass [kg/m]
    real(wp), intent(in) :: v(:,:)         !! particle velocity [m/s]
    real(wp), intent(inout) :: gmass(:)    !! node mass [kg/m]
    real(wp), intent(inout) :: gmom(:,:)   !! node momentum [kg/s]
    integer :: ip, a, b, k, n
    real(wp) :: wm
    gmass = 0.0_wp
    gmom = 0.0_wp
    !$omp parallel do default(none) schedule(static) shared(np, nb, nx, blk, w, mass, v) &
    !$omp   private(ip, a, b, k, n, wm) reduction(+: gmass, gmom)
    do ip = 1, np
      do b = 0, nb - 1
        n = 1 + blk(1, ip) + nx*(blk(2, ip) + b)
        do a = 0, nb - 1
          k = 1 + a + nb*b
          wm = w(k, ip)*mass(ip)
          gmass(n + a) = gmass(n + a) + wm
          gmom(1, n + a) = gmom(1, n + a) + wm*v(1, ip)
          gmom(2, n + a) = gmom(2, n + a) + wm*v(2, ip)
        end do
      end do
    end do
    !$omp end parallel do
  end subroutine p2g_mass_kernel

  !> Internal force -V sigma . grad phi and body force phi m (g + b_p) (METHOD.md sec. 2).
  subroutine p2g_force_kernel(np, nb, nx, blk, w, gw, mass, vol, stress, gravity, has_bacc, &
                              bacc, gforce)
    integer, intent(in) :: np, nb, nx      !! particles, block width, nodes along x
    integer, intent(in) :: blk(:,:)        !! block origins (2, np)
    real(wp), intent(in) :: w(:,:)         !! weights (nb*nb, np)
    real(wp), intent(in) :: gw(:,:,:)      !! gradients (2, nb*nb, np) [1/m]
    real(wp), intent(in) :: mass(:)        !! particle mass [kg/m]
    real(wp), intent(in) :: vol(:)         !! particle area [m^2]
    real(wp), intent(in) :: stress(:,:)    !! Cauchy stress (4, np) [Pa]
    real(wp), intent(in) :: gravity(2)     !! gravity [m/s^2]
    logical, intent(in) :: has_bacc        !! per-particle body acceleration given
    real(wp), intent(in), allocatable :: bacc(:,:)  !! body acceleration (2, np) [m/s^2]
    real(wp), intent(inout) :: gforce(:,:) !! node force [N/m]
    integer :: ip, a, b, k, n
    real(wp) :: sxx, syy, sxy, vp, fb(2)
    gforce = 0.0_wp
    !$omp parallel do default(none) schedule(static) &
    !$omp   shared(np, nb, nx, blk, w, gw, mass, vol, stress, gravity, has_bacc, bacc) &
    !$omp   private(ip, a, b, k, n, sxx, syy, sxy, vp, fb) reduction(+: gforce)
    do ip = 1, np
      vp = vol(ip)
      sxx = vp*stress(1, ip)
      syy = vp*stress(2, ip)
      sxy = vp*stress(3, ip)
      fb = mass(ip)*gravity
      if (has_bacc) fb = fb + mass(ip)*bacc(:, ip)
      do b = 0, nb - 1
        n = 1 + blk(1, ip) + nx*(blk(2, ip) + b)
        do a = 0, nb - 1
          k = 1 + a + nb*b
          gforce(1, n + a) = gforce(1, n + a) - (sxx*gw(1, k, ip) + sxy*gw(2, k, ip)) &
                             + w(k, ip)*fb(1)
          gforce(2, n + a) = gforce(2, n + a) - (sxy*gw(1, k, ip) + syy*gw(2, k, ip)) &
                             + w(k, ip)*fb(2)
        end do
      end do
    end do
    !$omp end parallel do
  end subroutine p2g_force_kernel

  !> Node velocity = momentum / mass on active nodes (zero elsewhere).
  subroutine grid_velocity_from_momentum(s)
    type(sim_t), intent(inout) :: s        !! simulation
    integer :: k, n
    s%g%vel = 0.0_wp
    do k = 1, s%g%nactive
      n = s%g%active(k)
      s%g%vel(:, n) = s%g%mom(:, n)/s%g%mass(n)
    end do
  end subroutine grid_velocity_from_momentum

  !> Step 3: momentum update with the nodal force and mass-proportional damping.
  !! vel = new velocity, dvel = its change (before the walls, which adjust both).
  subroutine grid_update(s, dt)
    type(sim_t), intent(inout) :: s        !! simulation
    real(wp), intent(in) :: dt             !! time step [s]
    integer :: k, n
    real(wp) :: v0(2), v1(2), fac, edamp
    s%g%vel = 0.0_wp
    s%g%dvel = 0.0_wp
    fac = 1.0_wp/(1.0_wp + s%damping*dt)      ! implicit decay of the damping term
    edamp = 0.0_wp
    do k = 1, s%g%nactive
      n = s%g%active(k)
      v0 = s%g%mom(:, n)/s%g%mass(n)
      v1 = v0 + dt*s%g%force(:, n)/s%g%mass(n)
      if (s%damping > 0.0_wp) then
        edamp = edamp + 0.5_wp*s%g%mass(n)*(1.0_wp - fac*fac)*dot_product(v1, v1)
        v1 = fac*v1
      end if
      s%g%vel(:, n) = v1
      s%g%dvel(:, n) = v1 - v0
    end do
    s%e_damped = s%e_damped + edamp
  end subroutine grid_update

  !> Walls on the nodes. With record, the momentum change is the wall's impulse and the
  !! velocity change also enters dvel (so FLIP sees the contact).
  subroutine apply_walls(s, dt, record)
    type(sim_t), intent(inout) :: s        !! simulation
    real(wp), intent(in) :: dt             !! time step [s]
    logical, intent(in) :: record          !! record reactions (step 3) or not (re-maps)
    integer :: iw, k, n
    real(wp) :: vw(2), xn(2), dist, dp(2), imp(2), tol
    if (s%nwall == 0) return
    if (record) call wall_gaps(s)
    tol = 1.0e-6_wp*s%g%h
    do iw = 1, s%nwall
      vw = wall_velocity(s%walls(iw), s%t + 0.5_wp*dt)
      imp = 0.0_wp
      do k = 1, s%g%nactive
        n = s%g%active(k)
        xn(1) = s%g%origin(1) + s%g%h*real(mod(n - 1, s%g%nx), wp)
        xn(2) = s%g%origin(2) + s%g%h*real((n - 1)/s%g%nx, wp)
        dist = dot_product(xn - s%walls(iw)%point, s%walls(iw)%normal) - tol
        call wall_constrain_node(s%walls(iw)%contact, s%walls(iw)%friction, &
               s%walls(iw)%normal, vw, dist, s%g%gap(iw, n), s%g%mass(n), dt, &
               s%g%vel(:, n), dp)
        if (record) then
          s%g%dvel(:, n) = s%g%dvel(:, n) + dp/s%g%mass(n)
          imp = imp + dp
        end if
      end do
      if (record) s%walls(iw)%impulse = s%walls(iw)%impulse + imp
    end do
  end subroutine apply_walls

  !> For every wall, the smallest distance to the plane of the material supported by each node:
  !! the lowest corner of each particle's domain (CPDI) or of its extent (linear, uGIMP).
  subroutine wall_gaps(s)
    type(sim_t), intent(inout) :: s        !! simulation
    integer :: iw, ip, a, b, k, n, nb, nx
    real(wp) :: nrm(2), pt(2), d, r1(2), r2(2), reach
    nb = s%nb
    nx = s%g%nx
    reach = 2.0_wp*s%g%h + s%dt*(s%vmax + 100.0_wp)   ! particles farther away cannot touch
    do iw = 1, s%nwall
      if (s%walls(iw)%contact == CONTACT_SLIP) cycle
      nrm = s%walls(iw)%normal
      pt = s%walls(iw)%point
      do k = 1, s%g%nactive
        s%g%gap(iw, s%g%active(k)) = huge(1.0_wp)
      end do
      do ip = 1, s%p%np
        d = dot_product(s%p%x(:, ip) - pt, nrm)
        if (d > reach + 4.0_wp*maxval(s%p%half(:, ip))) cycle
        select case (s%basis)
        case (BASIS_CPDI2)
          d = huge(1.0_wp)
          do a = 1, 4
            d = min(d, dot_product(s%p%xc(:, s%p%corner(a, ip)) - pt, nrm))
          end do
        case (BASIS_CPDI1)
          r1 = matmul(s%p%F(:, :, ip), s%p%r10(:, ip))
          r2 = matmul(s%p%F(:, :, ip), s%p%r20(:, ip))
          d = d - abs(dot_product(r1, nrm)) - abs(dot_product(r2, nrm))
        case default
          d = d - s%p%half(1, ip)*abs(nrm(1)) - s%p%half(2, ip)*abs(nrm(2))
        end select
        if (d > reach) cycle
        do b = 0, nb - 1
          do a = 0, nb - 1
            if (s%w(1 + a + nb*b, ip) == 0.0_wp) cycle
            n = 1 + s%blk(1, ip) + a + nx*(s%blk(2, ip) + b)
            s%g%gap(iw, n) = min(s%g%gap(iw, n), d)
          end do
        end do
      end do
    end do
  end subroutine wall_gaps

  !> Step 4: FLIP/PIC velocity blend and position update (METHOD.md sec. 2, step 3);
  !! also the kinetic energy, the largest speed and the work of body forces.
  subroutine g2p(s, dt)
    type(sim_t), intent(inout) :: s        !! simulation
    real(wp), intent(in) :: dt             !! time step [s]
    integer :: ip, a, b, k, n, nb, nx
    real(wp) :: vpic(2), dv(2), vnew(2), flip, ekin, vmax, wgrav, fb(2)
    logical :: has_bacc
    nb = s%nb
    nx = s%g%nx
    flip = s%flip
    has_bacc = allocated(s%bacc)
    ekin = 0.0_wp
    vmax = 0.0_wp
    wgrav = 0.0_wp
    !$omp parallel do default(none) schedule(static) &
    !$omp   shared(s, nb, nx, flip, dt, has_bacc) private(ip, a, b, k, n, vpic, dv, vnew, fb) &
    !$omp   reduction(+: ekin, wgrav) reduction(max: vmax)
    do ip = 1, s%p%np
      vpic = 0.0_wp
      dv = 0.0_wp
      do b = 0, nb - 1
        n = 1 + s%blk(1, ip) + nx*(s%blk(2, ip) + b)
        do a = 0, nb - 1
          k = 1 + a + nb*b
          vpic = vpic + s%w(k, ip)*s%g%vel(:, n + a)
          dv = dv + s%w(k, ip)*s%g%dvel(:, n + a)
        end do
      end do
      vnew = flip*(s%p%v(:, ip) + dv) + (1.0_wp - flip)*vpic
      fb = s%gravity
      if (has_bacc) fb = fb + s%bacc(:, ip)
      wgrav = wgrav + s%p%mass(ip)*dot_product(fb, 0.5_wp*(s%p%v(:, ip) + vnew))*dt
      s%p%v(:, ip) = vnew
      s%p%x(:, ip) = s%p%x(:, ip) + dt*vpic
      ekin = ekin + 0.5_wp*s%p%mass(ip)*dot_product(vnew, vnew)
      vmax = max(vmax, dot_product(vnew, vnew))
    end do
    !$omp end parallel do
    s%e_kin = ekin
    s%vmax = sqrt(vmax)
    s%w_gravity = s%w_gravity + wgrav
  end subroutine g2p

  !> Step 6: L = sum v_i (x) grad phi, F <- (I + dt L) F, V = det(F) V0, stress update;
  !! accumulates plastic dissipation and the stored elastic energy; stops on det F <= 0,
  !! non-finite values or a failed return mapping.
  subroutine update_deformation(s, dt, stat, errmsg)
    type(sim_t), intent(inout) :: s        !! simulation
    real(wp), intent(in) :: dt             !! time step [s]
    integer, intent(out) :: stat           !! 0 or EXIT_NUMERIC
    character(len=:), allocatable, intent(out) :: errmsg  !! what failed
    integer :: ip, a, b, k, n, nb, nx, mstat, bad_j, bad_m, bad_f
    real(wp) :: L(2, 2), Fn(2, 2), J, dwp, eplast, estrain, vel(2)
    nb = s%nb
    nx = s%g%nx
    eplast = 0.0_wp
    estrain = 0.0_wp
    bad_j = 0; bad_m = 0; bad_f = 0
    stat = 0
    errmsg = ''
    !$omp parallel do default(none) schedule(static) shared(s, nb, nx, dt) &
    !$omp   private(ip, a, b, k, n, L, Fn, J, dwp, mstat, vel) &
    !$omp   reduction(+: eplast, estrain) reduction(max: bad_j, bad_m, bad_f)
    do ip = 1, s%p%np
      L = 0.0_wp
      do b = 0, nb - 1
        n = 1 + s%blk(1, ip) + nx*(s%blk(2, ip) + b)
        do a = 0, nb - 1
          k = 1 + a + nb*b
          vel = s%g%vel(:, n + a)
          L(1, 1) = L(1, 1) + vel(1)*s%gw(1, k, ip)
          L(1, 2) = L(1, 2) + vel(1)*s%gw(2, k, ip)
          L(2, 1) = L(2, 1) + vel(2)*s%gw(1, k, ip)
          L(2, 2) = L(2, 2) + vel(2)*s%gw(2, k, ip)
        end do
      end do
      Fn(1, 1) = s%p%F(1, 1, ip) + dt*(L(1, 1)*s%p%F(1, 1, ip) + L(1, 2)*s%p%F(2, 1, ip))
      Fn(1, 2) = s%p%F(1, 2, ip) + dt*(L(1, 1)*s%p%F(1, 2, ip) + L(1, 2)*s%p%F(2, 2, ip))
      Fn(2, 1) = s%p%F(2, 1, ip) + dt*(L(2, 1)*s%p%F(1, 1, ip) + L(2, 2)*s%p%F(2, 1, ip))
      Fn(2, 2) = s%p%F(2, 2, ip) + dt*(L(2, 1)*s%p%F(1, 2, ip) + L(2, 2)*s%p%F(2, 2, ip))
      J = Fn(1, 1)*Fn(2, 2) - Fn(1, 2)*Fn(2, 1)
      if (.not. J > 0.0_wp) then               ! also catches NaN
        bad_j = max(bad_j, ip)
        cycle
      end if
      s%p%F(:, :, ip) = Fn
      s%p%vol(ip) = J*s%p%vol0(ip)
      call material_stress_update(s%mats(s%p%mat(ip)), s%plane, L, dt, Fn, s%p%stress(:, ip), &
                                  s%p%eqps(ip), dwp, mstat)
      if (mstat /= 0) then
        bad_m = max(bad_m, ip)
        cycle
      end if
      if (.not. (ieee_is_finite(s%p%stress(1, ip)) .and. ieee_is_finite(s%p%stress(2, ip)) &
                 .and. ieee_is_finite(s%p%stress(3, ip)) .and. ieee_is_finite(s%p%v(1, ip)) &
                 .and. ieee_is_finite(s%p%v(2, ip)))) then
        bad_f = max(bad_f, ip)
        cycle
      end if
      s%p%wplastic(ip) = s%p%wplastic(ip) + s%p%vol(ip)*dwp
      eplast = eplast + s%p%vol(ip)*dwp
      estrain = estrain + s%p%vol(ip)*material_energy_density(s%mats(s%p%mat(ip)), s%plane, &
                s%p%stress(:, ip), Fn)
    end do
    !$omp end parallel do
    s%e_plastic = s%e_plastic + eplast
    s%e_strain = estrain
    if (bad_j > 0) then
      stat = EXIT_NUMERIC
      errmsg = 'det F <= 0 (inverted material) at particle '//itoa(bad_j)//' at ('// &
        rtoa(s%p%x(1, bad_j))//', '//rtoa(s%p%x(2, bad_j))//') m, step '//itoa(s%step)// &
        ', t = '//rtoa(s%t)//' s. Remedy: a smaller cfl, a finer grid (h below the wall '// &
        'thickness), or another basis (cpdi2 is the most robust)'
    else if (bad_m > 0) then
      stat = EXIT_NUMERIC
      errmsg = 'the stress update did not converge at particle '//itoa(bad_m)//' at ('// &
        rtoa(s%p%x(1, bad_m))//', '//rtoa(s%p%x(2, bad_m))//') m, step '//itoa(s%step)// &
        ', t = '//rtoa(s%t)//' s. Remedy: a smaller cfl or dt'
    else if (bad_f > 0) then
      stat = EXIT_NUMERIC
      errmsg = 'non-finite stress or velocity at particle '//itoa(bad_f)//', step '// &
        itoa(s%step)//', t = '//rtoa(s%t)//' s. Remedy: a smaller cfl or dt'
    end if
  end subroutine update_deformation

  !> Step 6 (domains): CPDI2 corners move with the grid velocity and the particle sits at the
  !! domain's centroid; CPDI1 half-vectors follow F (computed where used).
  subroutine update_domains(s, dt)
    type(sim_t), intent(inout) :: s        !! simulation
    real(wp), intent(in) :: dt             !! time step [s]
    integer :: ic, ip, i0, j0, n, nx
    real(wp) :: w4(4), v(2), xq(2, 4), area, cen(2), dev
    if (s%basis /= BASIS_CPDI2) return
    nx = s%g%nx
    !$omp parallel do default(none) schedule(static) shared(s, dt, nx) &
    !$omp   private(ic, i0, j0, n, w4, v)
    do ic = 1, s%p%nc
      call bilinear_at(s%p%xc(:, ic), s%g%origin, s%g%h, i0, j0, w4)
      n = 1 + i0 + nx*j0
      v = w4(1)*s%g%vel(:, n) + w4(2)*s%g%vel(:, n + 1) + w4(3)*s%g%vel(:, n + nx) &
          + w4(4)*s%g%vel(:, n + nx + 1)
      s%p%xc(:, ic) = s%p%xc(:, ic) + dt*v
    end do
    !$omp end parallel do
    dev = 0.0_wp
    !$omp parallel do default(none) schedule(static) shared(s) private(ip, xq, area, cen) &
    !$omp   reduction(max: dev)
    do ip = 1, s%p%np
      xq(:, 1) = s%p%xc(:, s%p%corner(1, ip))
      xq(:, 2) = s%p%xc(:, s%p%corner(2, ip))
      xq(:, 3) = s%p%xc(:, s%p%corner(3, ip))
      xq(:, 4) = s%p%xc(:, s%p%corner(4, ip))
      call quad_area_centroid(xq, area, cen)
      s%p%x(:, ip) = cen
      dev = max(dev, abs(area/s%p%vol(ip) - 1.0_wp))
    end do
    !$omp end parallel do
    s%area_dev = max(s%area_dev, dev)
  end subroutine update_domains



end module mpm_solver
