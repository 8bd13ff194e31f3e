!> The simulation state and one explicit MPM time step (METHOD.md sec. 2).
! SPDX-License-Identifier: MIT
!
! One step, as numbered in docs/algorithm.md:
!   1. basis: node block, weights and gradients of every particle (once per step, reused);
!      the particles are binned into grid tiles (mpm_grid), which bound the live region
!   2. P2G: mass, momentum, internal and body forces in one pass (USF: mass and momentum,
!      stress update, then forces)
!   3. grid update, damping, walls (reaction = momentum removed / dt)
!   4. G2P: FLIP/PIC velocity blend, positions
!   5. MUSL: momenta mapped back to the grid (the mass is unchanged), walls re-applied
!   6. deformation: L, F, volume, stress; CPDI domains (corners / half-vectors)
!   7. energies and health checks
! Everything is per unit depth inside; outputs scale by depth (and the sector factor).
!
! Performance (docs/performance.md): grid loops visit the live tiles only (mass, momentum and
! force are zero outside them), so no step touches the whole grid. P2G accumulates per thread
! (thread 0 into the grid, the others into buffers added on the live tiles); with
! `deterministic` it is a four-colour sweep over the tiles instead, whose sums do not depend on
! the thread count. Particle sums (energies) are formed per fixed chunk of particles, node sums
! (wall impulses, damping) per live span, and added in order, so they do not depend on the
! thread count either. Loops run in parallel only from sim_t%parallel_min particles on. Every
! per-particle operation is the same, in the same order, as in the plain serial algorithm, so
! one-thread results are bit-identical to it. The only allocation in a step is errmsg = ''.
module mpm_solver
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  !$ use omp_lib, only: omp_get_thread_num, omp_get_num_threads, omp_get_max_threads
  use mpm_kinds, only: wp, i8
  use mpm_constants, only: EXIT_NUMERIC, BASIS_LINEAR, BASIS_UGIMP, BASIS_CPDI1, &
                           BASIS_CPDI2, SCHEME_USF, SCHEME_MUSL, CONTACT_SLIP
  use mpm_particles, only: particles_t, quad_area_centroid, particles_memory_bytes
  use mpm_grid, only: grid_t, grid_grow, grid_set_tiles, grid_clear_live, grid_span, &
                      grid_thread_buffers, grid_memory_bytes
  use mpm_walls, only: wall_t, wall_velocity, wall_constrain_node, wall_travel
  use mpm_material, only: material_t, material_stress_update, material_energy_density
  use mpm_basis, only: weights_linear, weights_ugimp, weights_cpdi1, weights_cpdi2, bilinear_at
  use mpm_timers, only: clock_seconds, n_phases, PHASE_BASIS, PHASE_P2G, PHASE_GRID, &
                        PHASE_G2P, PHASE_REMAP, PHASE_STRESS, PHASE_CORNERS, PHASE_OTHER
  use mpm_strings, only: itoa, rtoa
  implicit none
  private
  public :: sim_t, solver_step, solver_stable_dt, solver_energies, solver_wall_point, &
            solver_init_energy, solver_memory_bytes

  integer, parameter :: chunk = 1024         !! particles per partial sum [-]
  integer, parameter :: tile_side = 4        !! grid tile side: bounds the live region [nodes]
  integer, parameter :: tile_side_colour = 16  !! tile side of the deterministic colour sweep:
                                             !! long particle runs, little halo [nodes]

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
    real(wp) :: growth_tol = 0.05_wp       !! energy growth, relative to max(E0, external
                                           !! work, e_floor), that counts as unstable [-]:
                                           !! runs well below the stable time step lose
                                           !! energy; near it they gain up to 4.7 %
                                           !! (docs/stability.md)
    real(wp) :: e_floor = 0.0_wp           !! kinetic energy of the bodies at the largest wall
                                           !! speed: the energy scale of the start of a
                                           !! crush, when the work done is still tiny [J/m]
    logical :: deterministic = .false.     !! results independent of the thread count
    integer :: parallel_min = 4096         !! particles from which loops run in parallel: below,
                                           !! OpenMP start-up and barriers cost more than they save
    integer :: colour_band = 32768         !! particles per band of the deterministic sweep
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
    ! per-step work arrays
    logical :: par = .false.               !! loops run in parallel this step
    integer, allocatable :: tile(:)        !! grid tile of each particle's block (np)
    integer, allocatable :: perm(:)        !! particles sorted by tile (deterministic) (np)
    integer, allocatable :: near(:)        !! particles near a wall, listed per chunk (np)
    integer, allocatable :: nnear(:)       !! near particles per chunk
    real(wp), allocatable :: chunk_sum(:,:) !! partial sums per chunk (2, nchunk)
    real(wp), allocatable :: wall_work(:,:) !! per wall: velocity over the step, point, normal
                                           !! (6, nwall) [m/s, m, -]
    real(wp) :: phase_time(n_phases) = 0.0_wp  !! wall time spent per phase (mpm_timers) [s]
    ! energies per unit depth of the modelled part [J/m]
    real(wp) :: e_kin = 0.0_wp, e_strain = 0.0_wp, e_plastic = 0.0_wp
    real(wp) :: e_external = 0.0_wp, e_damped = 0.0_wp, e0 = 0.0_wp
    real(wp) :: w_gravity = 0.0_wp         !! work of gravity and body forces [J/m]
    real(wp) :: energy_error = 0.0_wp      !! largest |balance| / max(E0, largest |external|) [-]
    real(wp) :: bal_max = 0.0_wp           !! largest |kin + strain + plastic + damped - ext - E0|
                                           !! [J/m]
    real(wp) :: ext_max = 0.0_wp           !! largest |external work| so far [J/m]
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

  !> Set the energies, E0 and the energy floor of the growth check from the initial state
  !! (walls and particles must be in place).
  subroutine solver_init_energy(s)
    type(sim_t), intent(inout) :: s        !! simulation
    integer :: ip, k
    real(wp) :: vwall, f
    call solver_energies(s, s%e_kin, s%e_strain)
    s%e0 = s%e_kin + s%e_strain
    vwall = 0.0_wp
    do k = 1, s%nwall
      f = 1.0_wp
      if (s%walls(k)%n_motion > 0) f = maxval(abs(s%walls(k)%motion_f(1:s%walls(k)%n_motion)))
      vwall = max(vwall, f*sqrt(dot_product(s%walls(k)%velocity, s%walls(k)%velocity)))
    end do
    s%e_floor = 0.5_wp*sum(s%p%mass(1:s%p%np))*vwall**2
    s%vmax = 0.0_wp
    do ip = 1, s%p%np
      s%vmax = max(s%vmax, sqrt(dot_product(s%p%v(:, ip), s%p%v(:, ip))))
    end do
  end subroutine solver_init_energy

  !> Memory held by the simulation: particles, basis cache, work arrays and grid [bytes].
  function solver_memory_bytes(s) result(b)
    type(sim_t), intent(in) :: s           !! simulation
    integer(i8) :: b
    b = particles_memory_bytes(s%p%np, s%p%nc) + grid_memory_bytes(s%g, s%nwall)
    if (allocated(s%w)) b = b + 8_i8*(size(s%w, kind=i8) + size(s%gw, kind=i8)) &
                          + 4_i8*size(s%blk, kind=i8)
    if (allocated(s%tile)) b = b + 4_i8*(size(s%tile, kind=i8) + size(s%perm, kind=i8) &
                             + size(s%near, kind=i8) + size(s%nnear, kind=i8)) &
                             + 8_i8*size(s%chunk_sum, kind=i8)
    if (allocated(s%bacc)) b = b + 8_i8*size(s%bacc, kind=i8)
  end function solver_memory_bytes

  !> Advance by one time step (clipped to end exactly at t_end).
  !! stat = EXIT_NUMERIC with a message naming what failed, where and the remedy.
  subroutine solver_step(s, stat, errmsg)
    type(sim_t), intent(inout) :: s        !! simulation
    integer, intent(out) :: stat           !! 0 or EXIT_NUMERIC
    character(len=:), allocatable, intent(out) :: errmsg  !! what failed
    real(wp) :: dt, emech, scale, excess, clock
    integer :: k
    logical :: remap
    stat = 0
    errmsg = ''
    clock = clock_seconds()
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
    s%par = s%p%np >= s%parallel_min
    call tick(s, PHASE_OTHER, clock)

    ! 1. basis: weights and gradients once per step, reused by every transfer; tiles
    call compute_basis(s, stat, errmsg)
    if (stat /= 0) return
    call bin_particles(s)
    call tick(s, PHASE_BASIS, clock)
    ! 2. P2G (USF: stress first, from the velocity mapped at the start of the step)
    if (s%scheme == SCHEME_USF) then
      call p2g(s, mass_momentum=.true., force=.false.)
      call grid_velocity_walls(s, dt)
      call tick(s, PHASE_P2G, clock)
      call update_deformation(s, dt, stat, errmsg)
      if (stat /= 0) return
      call tick(s, PHASE_STRESS, clock)
      call p2g(s, mass_momentum=.false., force=.true.)
    else
      call p2g(s, mass_momentum=.true., force=.true.)   ! the stress is the previous step's
    end if
    call tick(s, PHASE_P2G, clock)
    ! 3. grid update, damping and walls
    call grid_update_walls(s, dt)
    call tick(s, PHASE_GRID, clock)
    ! 4. G2P (and 5. the MUSL momentum map in the same pass)
    remap = s%scheme == SCHEME_MUSL
    if (remap .and. s%deterministic) then
      call g2p_coloured(s, dt)
    else
      call g2p(s, dt, remap)
    end if
    call tick(s, PHASE_G2P, clock)
    ! 5. MUSL: the new particle momenta back on the grid, walls re-applied
    if (remap) then
      call grid_velocity_walls(s, dt)
      call tick(s, PHASE_REMAP, clock)
    end if
    ! 6. deformation and stress (USF did it in step 2), then the particle domains
    if (s%scheme /= SCHEME_USF) then
      call update_deformation(s, dt, stat, errmsg)
      if (stat /= 0) return
      call tick(s, PHASE_STRESS, clock)
    end if
    call update_domains(s, dt)
    call tick(s, PHASE_CORNERS, clock)

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
    ! energy_error as INTERFACE.md defines it: the largest imbalance over the run divided by
    ! max(E0, the largest external work), both maxima over the run so far
    excess = emech - s%e_external - s%e0
    s%bal_max = max(s%bal_max, abs(excess))
    s%ext_max = max(s%ext_max, abs(s%e_external))
    scale = max(s%e0, s%ext_max, tiny(1.0_wp))
    s%energy_error = s%bal_max/scale
    call tick(s, PHASE_OTHER, clock)
    if (s%step > 10_i8 .and. (excess > s%energy_tol*scale .or. &
                              excess > s%growth_tol*max(scale, s%e_floor))) then
      stat = EXIT_NUMERIC
      errmsg = 'energy growth (instability) at step '//itoa(s%step)//', t = '//rtoa(s%t)// &
        ' s: kinetic + elastic + plastic + damped energy exceeds the initial energy plus the '// &
        'work put in by '//rtoa(100.0_wp*excess/scale)//' % (runs below the stable time '// &
        'step lose energy or gain a few %). The time step dt = '//rtoa(dt)//' s (cfl = '// &
        rtoa(dt*(s%c_max + s%vmax)/s%g%h)//') is probably above the stable limit of this '// &
        'basis and scheme (docs/stability.md): lower cfl (0.1 to 0.3) or dt'
      return
    end if
  end subroutine solver_step

  !> Where and when a step failed, for the messages: 'step N, t = T s, time step dt = X s
  !! (cfl C)'.
  function step_context(s) result(text)
    type(sim_t), intent(in) :: s           !! simulation (s%dt is the step being taken)
    character(len=:), allocatable :: text
    text = 'step '//itoa(s%step + 1_i8)//', t = '//rtoa(s%t)//' s, time step dt = '// &
           rtoa(s%dt)//' s (cfl '//rtoa(s%dt*(s%c_max + s%vmax)/s%g%h)//')'
  end function step_context

  !> Add the time since `clock` to phase `phase`; clock becomes now.
  subroutine tick(s, phase, clock)
    type(sim_t), intent(inout) :: s        !! simulation
    integer, intent(in) :: phase           !! PHASE_* code
    real(wp), intent(inout) :: clock       !! last reading [s]
    real(wp) :: now
    now = clock_seconds()
    s%phase_time(phase) = s%phase_time(phase) + (now - clock)
    clock = now
  end subroutine tick

  !> Step 1: block, weights and gradients of every particle; grows the block width and the
  !! grid as needed; detects folded CPDI2 domains and particles leaving a fixed grid.
  subroutine compute_basis(s, stat, errmsg)
    type(sim_t), intent(inout) :: s        !! simulation
    integer, intent(out) :: stat           !! 0 or EXIT_NUMERIC
    character(len=:), allocatable, intent(inout) :: errmsg  !! what failed (set on failure)
    integer :: ip, ic, nchunk, need_max, lo(2), hi(2), add(4), bad, attempt, nb, nx, ny
    real(wp) :: origin(2), h, jmin_all
    stat = 0
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
      nchunk = (s%p%np + chunk - 1)/chunk
      !$omp parallel do default(none) schedule(static) shared(s, origin, h, nb, nchunk) &
      !$omp   private(ic) reduction(max: need_max, bad, hi) reduction(min: lo, jmin_all) &
      !$omp   if(s%par)
      do ic = 1, nchunk
        call basis_kernel(1 + (ic - 1)*chunk, min(ic*chunk, s%p%np), s%p%np, s%p%nc, &
               s%basis, nb, origin, h, s%p%x, s%p%half, s%p%F, s%p%r10, s%p%r20, s%p%corner, &
               s%p%xc, s%blk, s%w, s%gw, need_max, lo, hi, bad, jmin_all)
      end do
      !$omp end parallel do
      if (s%basis == BASIS_CPDI2) s%jmin_seen = min(s%jmin_seen, jmin_all)
      if (bad > 0) then
        stat = EXIT_NUMERIC
        errmsg = 'folded CPDI2 domain: the domain of particle '//itoa(bad)//' at ('// &
          rtoa(s%p%x(1, bad))//', '//rtoa(s%p%x(2, bad))//') m folded or inverted '// &
          '(corner Jacobian <= 0) at '//step_context(s)//'. Remedy: near full crush (the '// &
          'inner walls meet from delta/D = 0.94) stop the crush at delta/D <= 0.9, or use '// &
          'basis = ''cpdi1'' or ''ugimp'' (their domains cannot fold); otherwise a smaller cfl '// &
          'and more particles through the wall (docs/stability.md)'
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
          rtoa(s%p%x(2, bad))//') m left the grid at '//step_context(s)//'. Remedy: '// &
          'enlarge &grid lower/upper, or omit them so that the grid is fitted and grows '// &
          'with the material; if the particle flew off, the time step was unstable: lower cfl'
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
    errmsg = 'non-finite positions: could not fit the grid to the particles at '// &
             step_context(s)//'. Remedy: lower cfl (the time step is above the stable limit)'
  end subroutine compute_basis

  !> Step 1 for particles ip0..ip1: block, weights and gradients; the largest block width
  !! needed, the node range touched, the last folded CPDI2 domain and the smallest corner
  !! Jacobian ratio (all merged into the caller's values).
  subroutine basis_kernel(ip0, ip1, np, nc, basis, nb, origin, h, x, half, F, r10, r20, &
                          corner, xc, blk, w, gw, need_max, lo, hi, bad, jmin_all)
    integer, intent(in) :: ip0, ip1        !! particles
    integer, intent(in) :: np, nc          !! particles, corners
    integer, intent(in) :: basis           !! BASIS_* code
    integer, intent(in) :: nb              !! block width [nodes]
    real(wp), intent(in) :: origin(2)      !! grid origin [m]
    real(wp), intent(in) :: h              !! cell size [m]
    real(wp), intent(in) :: x(2, np)       !! positions [m]
    real(wp), intent(in) :: half(2, np)    !! uGIMP half sizes [m]
    real(wp), intent(in) :: F(2, 2, np)    !! deformation gradients [-]
    real(wp), intent(in) :: r10(2, np), r20(2, np)  !! initial CPDI1 half-vectors [m]
    integer, intent(in) :: corner(4, np)   !! corner ids
    real(wp), intent(in) :: xc(2, nc)      !! corner positions [m]
    integer, intent(out) :: blk(2, np)     !! lower-left node of each block
    real(wp), intent(out) :: w(nb*nb, np)  !! weights [-]
    real(wp), intent(out) :: gw(2, nb*nb, np)  !! gradients [1/m]
    integer, intent(inout) :: need_max     !! largest block width needed
    integer, intent(inout) :: lo(2), hi(2) !! node range touched
    integer, intent(inout) :: bad          !! last particle with a folded CPDI2 domain (or 0)
    real(wp), intent(inout) :: jmin_all    !! smallest CPDI2 corner Jacobian ratio [-]
    integer :: ip, need
    real(wp) :: xq(2, 4), jmin
    do ip = ip0, ip1
      select case (basis)
      case (BASIS_LINEAR)
        call weights_linear(x(:, ip), origin, h, nb, blk(1, ip), blk(2, ip), w(:, ip), &
                            gw(:, :, ip), need)
      case (BASIS_UGIMP)
        call weights_ugimp(x(:, ip), half(:, ip), origin, h, nb, blk(1, ip), blk(2, ip), &
                           w(:, ip), gw(:, :, ip), need)
      case (BASIS_CPDI1)
        call weights_cpdi1(x(:, ip), matmul(F(:, :, ip), r10(:, ip)), &
                           matmul(F(:, :, ip), r20(:, ip)), origin, h, nb, blk(1, ip), &
                           blk(2, ip), w(:, ip), gw(:, :, ip), need)
      case default
        xq(:, 1) = xc(:, corner(1, ip))
        xq(:, 2) = xc(:, corner(2, ip))
        xq(:, 3) = xc(:, corner(3, ip))
        xq(:, 4) = xc(:, corner(4, ip))
        call weights_cpdi2(xq, origin, h, nb, blk(1, ip), blk(2, ip), w(:, ip), gw(:, :, ip), &
                           need, jmin)
        if (.not. jmin > 0.0_wp) bad = max(bad, ip)
        jmin_all = min(jmin_all, jmin)
      end select
      need_max = max(need_max, need)
      lo = min(lo, blk(:, ip))
      ! the transfers run over the whole nb x nb block (zero weights past `need`), so the
      ! grid must hold all of it, not just the part this particle needs
      hi = max(hi, blk(:, ip) + max(nb, need) - 1)
    end do
  end subroutine basis_kernel

  !> (Re)allocate the per-step basis cache for the current block width, and (once) the
  !! per-particle work arrays.
  subroutine allocate_cache(s)
    type(sim_t), intent(inout) :: s        !! simulation
    integer :: np
    np = s%p%np
    if (allocated(s%w)) deallocate(s%w, s%gw, s%blk)
    allocate(s%blk(2, np), s%w(s%nb*s%nb, np), s%gw(2, s%nb*s%nb, np))
    if (.not. allocated(s%tile)) then
      allocate(s%tile(np), s%perm(np), s%near(np), s%nnear((np + chunk - 1)/chunk), &
               s%chunk_sum(2, (np + chunk - 1)/chunk))
    end if
  end subroutine allocate_cache

  !> Bin the particles into grid tiles (by the lower-left node of their block): mark the
  !! occupied tiles, clear the previous live region, list the new live tiles, and for the
  !! deterministic scatter sort the particles by tile and group the tiles by colour.
  subroutine bin_particles(s)
    type(sim_t), intent(inout) :: s        !! simulation
    integer :: ts
    ! tiles must hold a block: nb <= ts + 1 (the colour sweep relies on it)
    ts = merge(tile_side_colour, tile_side, s%deterministic)
    do while (ts + 1 < s%nb)
      ts = 2*ts
    end do
    call grid_set_tiles(s%g, ts, s%par)
    if (s%g%stamp == huge(1)) then
      s%g%occupied = 0
      s%g%stamp = 0
    end if
    s%g%stamp = s%g%stamp + 1
    call mark_tiles(s%p%np, s%g%ts_shift, s%g%ntx, s%g%stamp, s%blk, s%tile, s%g%occupied, &
                    s%par)
    call grid_clear_live(s%g, s%par)
    call list_live_tiles(s%g)
    if (s%deterministic) call sort_by_tile(s)
    if (.not. allocated(s%g%span_sum)) allocate(s%g%span_sum(1 + 2*s%nwall, size(s%g%span, 2)))
  end subroutine bin_particles

  !> Tile of every particle's block, and the stamp on every occupied tile.
  subroutine mark_tiles(np, shift, ntx, stamp, blk, tile, occupied, par)
    integer, intent(in) :: np              !! particles
    integer, intent(in) :: shift           !! log2 of the tile side
    integer, intent(in) :: ntx             !! tiles along x
    integer, intent(in) :: stamp           !! this pass's mark
    integer, intent(in) :: blk(2, np)      !! lower-left node of each block (0-based)
    integer, intent(out) :: tile(np)       !! tile id of each particle
    integer, intent(inout) :: occupied(:)  !! stamp of the last pass binning into each tile
    logical, intent(in) :: par             !! run in parallel
    integer :: ip, t
    !$omp parallel do default(none) schedule(static) shared(np, shift, ntx, stamp, blk, tile, &
    !$omp   occupied) private(ip, t) if(par)
    do ip = 1, np
      t = 1 + ishft(blk(1, ip), -shift) + ntx*ishft(blk(2, ip), -shift)
      tile(ip) = t
      !$omp atomic write
      occupied(t) = stamp
    end do
    !$omp end parallel do
  end subroutine mark_tiles

  !> Live tiles: occupied tiles and their right, upper and upper-right neighbours (a block
  !! reaches at most one tile further in x and y), as spans of consecutive live tiles in each
  !! tile row, ascending.
  subroutine list_live_tiles(g)
    type(grid_t), intent(inout) :: g       !! grid
    integer :: tx, ty, t, k, st, first
    logical :: live
    st = g%stamp
    k = 0
    do ty = 0, g%nty - 1
      first = -1
      do tx = 0, g%ntx
        live = .false.
        if (tx < g%ntx) then
          t = 1 + tx + g%ntx*ty
          live = g%occupied(t) == st
          if (tx > 0) live = live .or. g%occupied(t - 1) == st
          if (ty > 0) then
            live = live .or. g%occupied(t - g%ntx) == st
            if (tx > 0) live = live .or. g%occupied(t - g%ntx - 1) == st
          end if
        end if
        if (live .and. first < 0) first = tx
        if (.not. live .and. first >= 0) then          ! a span ends before tx
          k = k + 1
          g%span(:, k) = [g%ts*first, min(g%ts*tx, g%nx) - 1, g%ts*ty, min(g%ts*(ty + 1), g%ny) - 1]
          first = -1
        end if
      end do
    end do
    g%nspan = k
  end subroutine list_live_tiles

  !> Deterministic scatter: a stable counting sort of the particles by tile (perm), and the
  !! occupied tiles in groups (band, colour): a band holds the tiles whose first particle is
  !! among the same s%colour_band consecutive particles, the colour is (tx mod 2, ty mod 2), and
  !! within a group the tiles follow their first particles. The sweeps take the groups in order,
  !! so that one band's particles and grid region stay in cache over its four colours.
  subroutine sort_by_tile(s)
    type(sim_t), intent(inout) :: s        !! simulation
    integer :: ip, t, i, ntiles
    associate (g => s%g)
      ntiles = g%ntx*g%nty
      g%ngroup = 4*((s%p%np + s%colour_band - 1)/s%colour_band)
      if (allocated(g%group_start)) then
        if (size(g%group_pos) < g%ngroup) deallocate(g%group_start, g%group_pos)
      end if
      if (.not. allocated(g%group_start)) allocate(g%group_start(g%ngroup + 1), &
                                                    g%group_pos(g%ngroup))
      g%tile_start = 0
      do ip = 1, s%p%np                      ! particles per tile (in tile_start(t + 1))
        g%tile_start(s%tile(ip) + 1) = g%tile_start(s%tile(ip) + 1) + 1
      end do
      g%group_start = 0
      do ip = 1, s%p%np                      ! tiles per group; a listed tile's count < 0
        t = s%tile(ip)
        if (g%tile_start(t + 1) <= 0) cycle
        i = tile_group(ip, t, g%ntx, s%colour_band)
        g%group_start(i + 1) = g%group_start(i + 1) + 1
        g%tile_start(t + 1) = -g%tile_start(t + 1)
      end do
      g%group_start(1) = 1
      do i = 1, g%ngroup
        g%group_start(i + 1) = g%group_start(i + 1) + g%group_start(i)
      end do
      g%group_pos = g%group_start(1:g%ngroup)
      do ip = 1, s%p%np                      ! the tiles, in the order of their first particle
        t = s%tile(ip)
        if (g%tile_start(t + 1) >= 0) cycle
        i = tile_group(ip, t, g%ntx, s%colour_band)
        g%colour_tiles(g%group_pos(i)) = t
        g%group_pos(i) = g%group_pos(i) + 1
        g%tile_start(t + 1) = -g%tile_start(t + 1)
      end do
      g%tile_start(1) = 1
      do t = 1, ntiles
        g%tile_start(t + 1) = g%tile_start(t + 1) + g%tile_start(t)
      end do
      do ip = 1, s%p%np                      ! tile_start(t) runs to the start of tile t + 1
        s%perm(g%tile_start(s%tile(ip))) = ip
        g%tile_start(s%tile(ip)) = g%tile_start(s%tile(ip)) + 1
      end do
      do t = ntiles, 1, -1
        g%tile_start(t + 1) = g%tile_start(t)
      end do
      g%tile_start(1) = 1
    end associate
  end subroutine sort_by_tile

  !> Group of tile t whose first particle is ip: 4 (band - 1) + colour, colour 1..4 =
  !! 1 + (tx mod 2) + 2 (ty mod 2).
  pure integer function tile_group(ip, t, ntx, band) result(i)
    integer, intent(in) :: ip              !! first particle of the tile
    integer, intent(in) :: t               !! tile id
    integer, intent(in) :: ntx             !! tiles along x
    integer, intent(in) :: band            !! particles per band
    i = 4*((ip - 1)/band) + 1 + mod(mod(t - 1, ntx), 2) + 2*mod((t - 1)/ntx, 2)
  end function tile_group

  !> Step 2: P2G of mass and momentum (with the active-node cut-off) and/or of the forces.
  subroutine p2g(s, mass_momentum, force)
    type(sim_t), intent(inout) :: s        !! simulation
    logical, intent(in) :: mass_momentum   !! map mass and momentum
    logical, intent(in) :: force           !! map internal and body forces
    if (s%deterministic) then
      call p2g_coloured(s, mass_momentum, force)
    else
      call p2g_threads(s, mass_momentum, force)
    end if
    if (mass_momentum) call set_mass_cut(s%g, s%par)
  end subroutine p2g

  !> P2G by per-thread accumulation: each thread maps a contiguous range of particles, thread 0
  !! into the grid and the others into their buffers, which are then added on the live tiles
  !! (and zeroed again).
  subroutine p2g_threads(s, do_mass, do_force)
    type(sim_t), intent(inout) :: s        !! simulation
    logical, intent(in) :: do_mass, do_force  !! map mass and momentum, forces
    integer :: it, nt, ip0, ip1, np, k
    logical :: has_bacc
    np = s%p%np
    has_bacc = allocated(s%bacc)
    nt = 1
    !$ if (s%par) nt = omp_get_max_threads()
    call grid_thread_buffers(s%g, nt)
    !$omp parallel default(none) shared(s, np, has_bacc, do_mass, do_force) &
    !$omp   private(it, nt, ip0, ip1, k) if(s%par)
    it = 0
    nt = 1
    !$ it = omp_get_thread_num()
    !$ nt = omp_get_num_threads()
    ip0 = 1 + int(int(np, i8)*int(it, i8)/int(nt, i8))
    ip1 = int(int(np, i8)*int(it + 1, i8)/int(nt, i8))
    if (it == 0) then
      call p2g_kernel(ip0, ip1, .false., s%perm, np, s%g%nn, s%nb, s%g%nx, s%blk, s%w, s%gw, &
                      s%p%mass, s%p%v, s%p%vol, s%p%stress, s%gravity, has_bacc, s%bacc, &
                      do_mass, do_force, s%g%mass, s%g%mom, s%g%force)
    else
      call p2g_kernel(ip0, ip1, .false., s%perm, np, s%g%nn, s%nb, s%g%nx, s%blk, s%w, s%gw, &
                      s%p%mass, s%p%v, s%p%vol, s%p%stress, s%gravity, has_bacc, s%bacc, &
                      do_mass, do_force, s%g%buf_mass(:, it), s%g%buf_mom(:, :, it), &
                      s%g%buf_force(:, :, it))
    end if
    if (nt > 1) then
      !$omp barrier
      !$omp do schedule(static)
      do k = 1, s%g%nspan
        call add_buffers(s%g, k, nt - 1, do_mass, do_mass, do_force)
      end do
      !$omp end do
    end if
    !$omp end parallel
  end subroutine p2g_threads

  !> Deterministic P2G: the occupied tiles of one colour write disjoint node sets (blocks fit
  !! in two tiles), so each group (band, colour) is a parallel loop over its tiles straight into
  !! the grid; every node sums its particles in (group, tile, index) order whatever the thread
  !! count.
  subroutine p2g_coloured(s, do_mass, do_force)
    type(sim_t), intent(inout) :: s        !! simulation
    logical, intent(in) :: do_mass, do_force  !! map mass and momentum, forces
    integer :: i, k, t, np
    logical :: has_bacc
    np = s%p%np
    has_bacc = allocated(s%bacc)
    !$omp parallel default(none) shared(s, np, has_bacc, do_mass, do_force) private(i, k, t) &
    !$omp   if(s%par)
    do i = 1, s%g%ngroup
      !$omp do schedule(dynamic, 2)
      do k = s%g%group_start(i), s%g%group_start(i + 1) - 1
        t = s%g%colour_tiles(k)
        call p2g_kernel(s%g%tile_start(t), s%g%tile_start(t + 1) - 1, .true., s%perm, np, &
                        s%g%nn, s%nb, s%g%nx, s%blk, s%w, s%gw, s%p%mass, s%p%v, s%p%vol, &
                        s%p%stress, s%gravity, has_bacc, s%bacc, do_mass, do_force, &
                        s%g%mass, s%g%mom, s%g%force)
      end do
      !$omp end do
    end do
    !$omp end parallel
  end subroutine p2g_coloured

  !> Scatter of particles k0..k1 (perm(k0..k1) when sorted): mass m_p phi, momentum
  !! m_p v_p phi, force -V sigma . grad phi + phi m_p (g + b_p) (METHOD.md sec. 2, step 1).
  subroutine p2g_kernel(k0, k1, sorted, perm, np, nn, nb, nx, blk, w, gw, mass, v, vol, &
                        stress, gravity, has_bacc, bacc, do_mass, do_force, &
                        gmass, gmom, gforce)
    integer, intent(in) :: k0, k1          !! range of particles (or of perm)
    logical, intent(in) :: sorted          !! particles are perm(k0..k1)
    integer, intent(in) :: np, nn, nb, nx  !! particles, nodes, block width, nodes along x
    integer, intent(in) :: perm(np)        !! particle order (sorted only)
    integer, intent(in) :: blk(2, np)      !! block origins
    real(wp), intent(in) :: w(nb*nb, np)   !! weights [-]
    real(wp), intent(in) :: gw(2, nb*nb, np)  !! gradients [1/m]
    real(wp), intent(in) :: mass(np)       !! particle mass [kg/m]
    real(wp), intent(in) :: v(2, np)       !! particle velocity [m/s]
    real(wp), intent(in) :: vol(np)        !! particle area [m^2]
    real(wp), intent(in) :: stress(4, np)  !! Cauchy stress [Pa]
    real(wp), intent(in) :: gravity(2)     !! gravity [m/s^2]
    logical, intent(in) :: has_bacc        !! per-particle body acceleration given
    real(wp), intent(in), allocatable :: bacc(:,:)  !! body acceleration (2, np) [m/s^2]
    logical, intent(in) :: do_mass, do_force  !! map mass and momentum, forces
    real(wp), intent(inout) :: gmass(nn)   !! node mass [kg/m]
    real(wp), intent(inout) :: gmom(2, nn) !! node momentum [kg/s]
    real(wp), intent(inout) :: gforce(2, nn)  !! node force [N/m]
    integer :: k, ip, a, b, kk, n
    real(wp) :: wm, sxx, syy, sxy, vp, fb(2)
    do k = k0, k1
      ip = k
      if (sorted) ip = perm(k)
      if (do_mass) then
        do b = 0, nb - 1
          n = 1 + blk(1, ip) + nx*(blk(2, ip) + b)
          do a = 0, nb - 1
            kk = 1 + a + nb*b
            wm = w(kk, ip)*mass(ip)
            gmass(n + a) = gmass(n + a) + wm
            gmom(1, n + a) = gmom(1, n + a) + wm*v(1, ip)
            gmom(2, n + a) = gmom(2, n + a) + wm*v(2, ip)
          end do
        end do
      end if
      if (do_force) then
        vp = vol(ip)
        sxx = vp*stress(1, ip)
        syy = vp*stress(2, ip)
        sxy = vp*stress(3, ip)
        fb = mass(ip)*gravity
        if (has_bacc) fb = fb + mass(ip)*bacc(:, ip)
        do b = 0, nb - 1
          n = 1 + blk(1, ip) + nx*(blk(2, ip) + b)
          do a = 0, nb - 1
            kk = 1 + a + nb*b
            gforce(1, n + a) = gforce(1, n + a) - (sxx*gw(1, kk, ip) + sxy*gw(2, kk, ip)) &
                               + w(kk, ip)*fb(1)
            gforce(2, n + a) = gforce(2, n + a) - (sxy*gw(1, kk, ip) + syy*gw(2, kk, ip)) &
                               + w(kk, ip)*fb(2)
          end do
        end do
      end if
    end do
  end subroutine p2g_kernel

  !> Add the thread buffers 1..nbuf to the grid on live span k, and zero them there.
  subroutine add_buffers(g, k, nbuf, do_mass, do_mom, do_force)
    type(grid_t), intent(inout) :: g       !! grid
    integer, intent(in) :: k               !! span index
    integer, intent(in) :: nbuf            !! buffers in use
    logical, intent(in) :: do_mass, do_mom, do_force  !! fields mapped
    integer :: i0, i1, j0, j1, j, n0, n1, ib
    call grid_span(g, k, i0, i1, j0, j1)
    do ib = 1, nbuf
      do j = j0, j1
        n0 = 1 + i0 + g%nx*j
        n1 = 1 + i1 + g%nx*j
        if (do_mass) then
          g%mass(n0:n1) = g%mass(n0:n1) + g%buf_mass(n0:n1, ib)
          g%buf_mass(n0:n1, ib) = 0.0_wp
        end if
        if (do_mom) then
          g%mom(:, n0:n1) = g%mom(:, n0:n1) + g%buf_mom(:, n0:n1, ib)
          g%buf_mom(:, n0:n1, ib) = 0.0_wp
        end if
        if (do_force) then
          g%force(:, n0:n1) = g%force(:, n0:n1) + g%buf_force(:, n0:n1, ib)
          g%buf_force(:, n0:n1, ib) = 0.0_wp
        end if
      end do
    end do
  end subroutine add_buffers

  !> Zero the node momentum on the live tiles (before the MUSL re-map).
  subroutine zero_momentum(g, par)
    type(grid_t), intent(inout) :: g       !! grid
    logical, intent(in) :: par             !! run in parallel
    integer :: k, i0, i1, j0, j1, j
    !$omp parallel do default(none) schedule(static) shared(g) private(k, i0, i1, j0, j1, j) &
    !$omp   if(par)
    do k = 1, g%nspan
      call grid_span(g, k, i0, i1, j0, j1)
      do j = j0, j1
        g%mom(:, 1 + i0 + g%nx*j:1 + i1 + g%nx*j) = 0.0_wp
      end do
    end do
    !$omp end parallel do
  end subroutine zero_momentum

  !> Active nodes: mass above 1e-12 of the largest (METHOD.md sec. 2).
  subroutine set_mass_cut(g, par)
    type(grid_t), intent(inout) :: g       !! grid
    logical, intent(in) :: par             !! run in parallel
    integer :: k, i0, i1, j0, j1, j
    real(wp) :: mmax
    mmax = 0.0_wp
    !$omp parallel do default(none) schedule(static) shared(g) private(k, i0, i1, j0, j1, j) &
    !$omp   reduction(max: mmax) if(par)
    do k = 1, g%nspan
      call grid_span(g, k, i0, i1, j0, j1)
      do j = j0, j1
        mmax = max(mmax, maxval(g%mass(1 + i0 + g%nx*j:1 + i1 + g%nx*j)))
      end do
    end do
    !$omp end parallel do
    g%mass_cut = 1.0e-12_wp*mmax
  end subroutine set_mass_cut

  !> Steps 2 (USF) and 5 (MUSL): node velocity = momentum / mass on active nodes (zero
  !! elsewhere), then the walls on each active node (no reactions recorded).
  subroutine grid_velocity_walls(s, dt)
    type(sim_t), intent(inout) :: s        !! simulation
    real(wp), intent(in) :: dt             !! time step [s]
    integer :: k, i0, i1, j0, j1, i, j, n
    real(wp) :: tol
    call wall_setup(s, dt, tol)
    !$omp parallel do default(none) schedule(static) shared(s, dt, tol) &
    !$omp   private(k, i0, i1, j0, j1, i, j, n) if(s%par)
    do k = 1, s%g%nspan
      call grid_span(s%g, k, i0, i1, j0, j1)
      do j = j0, j1
        do i = i0, i1
          n = 1 + i + s%g%nx*j
          if (s%g%mass(n) > s%g%mass_cut) then
            s%g%vel(:, n) = s%g%mom(:, n)/s%g%mass(n)
            if (s%nwall > 0) call node_walls(s, i, j, n, dt, tol, 0)
          else
            s%g%vel(:, n) = 0.0_wp
          end if
        end do
      end do
    end do
    !$omp end parallel do
  end subroutine grid_velocity_walls

  !> Step 3: momentum update with the nodal force and mass-proportional damping, then the
  !! walls, node by node. vel = new velocity, dvel = its change (with the walls' part, so that
  !! FLIP sees the contact); the momentum the walls add is their impulse on the material.
  subroutine grid_update_walls(s, dt)
    type(sim_t), intent(inout) :: s        !! simulation
    real(wp), intent(in) :: dt             !! time step [s]
    integer :: k, i0, i1, j0, j1, i, j, n, nact, iw
    real(wp) :: v0(2), v1(2), fac, edamp, damping, tol
    call wall_setup(s, dt, tol)
    if (s%nwall > 0) call wall_gaps(s)
    fac = 1.0_wp/(1.0_wp + s%damping*dt)      ! implicit decay of the damping term
    damping = s%damping
    nact = 0
    !$omp parallel do default(none) schedule(static) shared(s, dt, fac, damping, tol) &
    !$omp   private(k, i0, i1, j0, j1, i, j, n, v0, v1, edamp) reduction(+: nact) if(s%par)
    do k = 1, s%g%nspan
      call grid_span(s%g, k, i0, i1, j0, j1)
      edamp = 0.0_wp
      s%g%span_sum(:, k) = 0.0_wp
      do j = j0, j1
        do i = i0, i1
          n = 1 + i + s%g%nx*j
          if (.not. s%g%mass(n) > s%g%mass_cut) then
            s%g%vel(:, n) = 0.0_wp
            s%g%dvel(:, n) = 0.0_wp
            cycle
          end if
          nact = nact + 1
          v0 = s%g%mom(:, n)/s%g%mass(n)
          v1 = v0 + dt*s%g%force(:, n)/s%g%mass(n)
          if (damping > 0.0_wp) then
            edamp = edamp + 0.5_wp*s%g%mass(n)*(1.0_wp - fac*fac)*dot_product(v1, v1)
            v1 = fac*v1
          end if
          s%g%vel(:, n) = v1
          s%g%dvel(:, n) = v1 - v0
          if (s%nwall > 0) call node_walls(s, i, j, n, dt, tol, k)
        end do
      end do
      s%g%span_sum(1, k) = edamp
    end do
    !$omp end parallel do
    s%g%nactive = nact
    s%e_damped = s%e_damped + sum(s%g%span_sum(1, 1:s%g%nspan))
    do iw = 1, s%nwall                     ! tile order: independent of the thread count
      do k = 1, s%g%nspan
        s%walls(iw)%impulse = s%walls(iw)%impulse + s%g%span_sum(2*iw:2*iw + 1, k)
      end do
    end do
  end subroutine grid_update_walls

  !> Per wall the velocity over the step, the point and the normal (s%wall_work), and the
  !! round-off tolerance of the 'slip' planes.
  subroutine wall_setup(s, dt, tol)
    type(sim_t), intent(inout) :: s        !! simulation
    real(wp), intent(in) :: dt             !! time step [s]
    real(wp), intent(out) :: tol           !! tolerance on the node distance [m]
    integer :: iw
    if (.not. allocated(s%wall_work)) allocate(s%wall_work(6, s%nwall))
    do iw = 1, s%nwall
      s%wall_work(1:2, iw) = wall_velocity(s%walls(iw), s%t + 0.5_wp*dt)
      s%wall_work(3:4, iw) = s%walls(iw)%point
      s%wall_work(5:6, iw) = s%walls(iw)%normal
    end do
    tol = 1.0e-6_wp*s%g%h
  end subroutine wall_setup

  !> The walls, in order, on active node n = (i, j) (METHOD.md sec. 5). With k > 0 (step 3)
  !! the velocity change also enters dvel and the momentum added is summed into the partial
  !! sums of span k. A wall other than 'slip' cannot act where no material is within reach
  !! (gap = huge); a 'slip' wall acts on the nodes on or behind its plane.
  subroutine node_walls(s, i, j, n, dt, tol, k)
    type(sim_t), intent(inout) :: s        !! simulation
    integer, intent(in) :: i, j, n         !! node indices and id
    real(wp), intent(in) :: dt             !! time step [s]
    real(wp), intent(in) :: tol            !! tolerance on the node distance [m]
    integer, intent(in) :: k               !! span of the node, or 0: no reactions recorded
    integer :: iw
    real(wp) :: xn(2), dist, dp(2)
    xn(1) = s%g%origin(1) + s%g%h*real(i, wp)
    xn(2) = s%g%origin(2) + s%g%h*real(j, wp)
    do iw = 1, s%nwall
      if (s%walls(iw)%contact == CONTACT_SLIP) then
        dist = dot_product(xn - s%wall_work(3:4, iw), s%wall_work(5:6, iw)) - tol
        if (dist > 0.0_wp) cycle
      else
        if (s%g%gap(iw, n) == huge(1.0_wp)) cycle
        dist = 0.0_wp                         ! (read by 'slip' only)
      end if
      call wall_constrain_node(s%walls(iw)%contact, s%walls(iw)%friction, &
                               s%wall_work(5:6, iw), s%wall_work(1:2, iw), dist, &
                               s%g%gap(iw, n), s%g%mass(n), dt, s%g%vel(:, n), dp)
      if (k > 0) then
        s%g%dvel(:, n) = s%g%dvel(:, n) + dp/s%g%mass(n)
        s%g%span_sum(2*iw:2*iw + 1, k) = s%g%span_sum(2*iw:2*iw + 1, k) + dp
      end if
    end do
  end subroutine node_walls

  !> For every wall but 'slip', the smallest distance to the plane of the material supported
  !! by each node: the lowest corner of each particle's domain (CPDI) or of its extent (linear,
  !! uGIMP); huge where no material is within reach. The particles that may be within reach
  !! are listed per chunk in parallel, then mapped to their nodes in order.
  subroutine wall_gaps(s)
    type(sim_t), intent(inout) :: s        !! simulation
    integer :: iw, ip, a, b, k, n, nb, nx, ic, nchunk, i0, i1, j0, j1, j, cnt
    real(wp) :: d, reach
    logical :: keep
    if (all(s%walls(:)%contact == CONTACT_SLIP)) return
    nb = s%nb
    nx = s%g%nx
    reach = 2.0_wp*s%g%h + s%dt*(s%vmax + 100.0_wp)   ! particles farther away cannot touch
    nchunk = (s%p%np + chunk - 1)/chunk
    !$omp parallel default(none) shared(s, reach, nchunk) &
    !$omp   private(iw, ip, k, i0, i1, j0, j1, j, ic, cnt, keep) if(s%par)
    !$omp do schedule(static)
    do k = 1, s%g%nspan
      call grid_span(s%g, k, i0, i1, j0, j1)
      do j = j0, j1
        do iw = 1, s%nwall
          if (s%walls(iw)%contact /= CONTACT_SLIP) &
            s%g%gap(iw, 1 + i0 + s%g%nx*j:1 + i1 + s%g%nx*j) = huge(1.0_wp)
        end do
      end do
    end do
    !$omp end do nowait
    !$omp do schedule(static)
    do ic = 1, nchunk
      cnt = 0
      do ip = 1 + (ic - 1)*chunk, min(ic*chunk, s%p%np)
        keep = .false.                       ! the first test of material_gap
        do iw = 1, s%nwall
          if (s%walls(iw)%contact == CONTACT_SLIP) cycle
          keep = keep .or. (s%p%x(1, ip) - s%wall_work(3, iw))*s%wall_work(5, iw) &
                           + (s%p%x(2, ip) - s%wall_work(4, iw))*s%wall_work(6, iw) &
                           <= reach + 4.0_wp*max(s%p%half(1, ip), s%p%half(2, ip))
        end do
        if (keep) then
          s%near(1 + (ic - 1)*chunk + cnt) = ip
          cnt = cnt + 1
        end if
      end do
      s%nnear(ic) = cnt
    end do
    !$omp end do
    !$omp end parallel
    do iw = 1, s%nwall
      if (s%walls(iw)%contact == CONTACT_SLIP) cycle
      do ic = 1, nchunk
        do j = 1, s%nnear(ic)
          ip = s%near((ic - 1)*chunk + j)
          d = material_gap(s, ip, iw, reach)
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
    end do
  end subroutine wall_gaps

  !> Distance from wall iw of the lowest point of particle ip's domain (corners for CPDI,
  !! the extent otherwise) [m]; huge when its centre is clearly beyond reach.
  pure function material_gap(s, ip, iw, reach) result(d)
    type(sim_t), intent(in) :: s           !! simulation
    integer, intent(in) :: ip, iw          !! particle, wall
    real(wp), intent(in) :: reach          !! largest distance of interest [m]
    real(wp) :: d, nrm(2), pt(2), r1(2), r2(2)
    integer :: a
    nrm = s%walls(iw)%normal
    pt = s%walls(iw)%point
    d = dot_product(s%p%x(:, ip) - pt, nrm)
    if (d > reach + 4.0_wp*maxval(s%p%half(:, ip))) then
      d = huge(1.0_wp)
      return
    end if
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
  end function material_gap

  !> Step 4: FLIP/PIC velocity blend and position update (METHOD.md sec. 2, step 3); also the
  !! kinetic energy, the largest speed and the work of body forces. With remap (MUSL, not
  !! deterministic), the new momenta go straight back to the grid (step 5) in the same pass,
  !! accumulated per thread like p2g_threads.
  subroutine g2p(s, dt, remap)
    type(sim_t), intent(inout) :: s        !! simulation
    real(wp), intent(in) :: dt             !! time step [s]
    logical, intent(in) :: remap           !! also map the new momenta to the grid
    integer :: it, nt, c0, c1, c, k, nchunk, np
    real(wp) :: vmax
    logical :: has_bacc
    has_bacc = allocated(s%bacc)
    np = s%p%np
    nchunk = (np + chunk - 1)/chunk
    if (remap) then
      call zero_momentum(s%g, s%par)
      nt = 1
      !$ if (s%par) nt = omp_get_max_threads()
      call grid_thread_buffers(s%g, nt)
    end if
    vmax = 0.0_wp
    !$omp parallel default(none) shared(s, dt, remap, has_bacc, nchunk, np) &
    !$omp   private(it, nt, c0, c1, c, k) reduction(max: vmax) if(s%par)
    it = 0
    nt = 1
    !$ it = omp_get_thread_num()
    !$ nt = omp_get_num_threads()
    c0 = 1 + (nchunk*it)/nt
    c1 = (nchunk*(it + 1))/nt
    do c = c0, c1
      if (it == 0 .or. .not. remap) then
        call g2p_kernel(1 + (c - 1)*chunk, min(c*chunk, np), .false., s%perm, np, s%g%nn, &
               s%nb, s%g%nx, s%blk, s%w, s%g%vel, s%g%dvel, s%flip, dt, s%gravity, has_bacc, &
               s%bacc, s%p%mass, s%p%v, s%p%x, remap, s%g%mom, s%chunk_sum(:, c), vmax)
      else
        call g2p_kernel(1 + (c - 1)*chunk, min(c*chunk, np), .false., s%perm, np, s%g%nn, &
               s%nb, s%g%nx, s%blk, s%w, s%g%vel, s%g%dvel, s%flip, dt, s%gravity, has_bacc, &
               s%bacc, s%p%mass, s%p%v, s%p%x, remap, s%g%buf_mom(:, :, it), &
               s%chunk_sum(:, c), vmax)
      end if
    end do
    if (remap .and. nt > 1) then
      !$omp barrier
      !$omp do schedule(static)
      do k = 1, s%g%nspan
        call add_buffers(s%g, k, nt - 1, .false., .true., .false.)
      end do
      !$omp end do
    end if
    !$omp end parallel
    s%e_kin = sum(s%chunk_sum(1, 1:nchunk))
    s%vmax = sqrt(vmax)
    s%w_gravity = s%w_gravity + sum(s%chunk_sum(2, 1:nchunk))
  end subroutine g2p

  !> Deterministic G2P with the MUSL momentum map: the particles tile by tile, group by group
  !! like p2g_coloured (the gathers do not care about the order; the momenta go straight into
  !! the grid), with the energy sums per tile, added in the fixed tile order.
  subroutine g2p_coloured(s, dt)
    type(sim_t), intent(inout) :: s        !! simulation
    real(wp), intent(in) :: dt             !! time step [s]
    integer :: i, k, t, np, ntile
    real(wp) :: vmax
    logical :: has_bacc
    has_bacc = allocated(s%bacc)
    np = s%p%np
    call zero_momentum(s%g, s%par)
    vmax = 0.0_wp
    !$omp parallel default(none) shared(s, dt, np, has_bacc) private(i, k, t) &
    !$omp   reduction(max: vmax) if(s%par)
    do i = 1, s%g%ngroup
      !$omp do schedule(dynamic, 2)
      do k = s%g%group_start(i), s%g%group_start(i + 1) - 1
        t = s%g%colour_tiles(k)
        call g2p_kernel(s%g%tile_start(t), s%g%tile_start(t + 1) - 1, .true., s%perm, np, &
               s%g%nn, s%nb, s%g%nx, s%blk, s%w, s%g%vel, s%g%dvel, s%flip, dt, s%gravity, &
               has_bacc, s%bacc, s%p%mass, s%p%v, s%p%x, .true., s%g%mom, &
               s%g%colour_sum(:, k), vmax)
      end do
      !$omp end do
    end do
    !$omp end parallel
    ntile = s%g%group_start(s%g%ngroup + 1) - 1
    s%e_kin = sum(s%g%colour_sum(1, 1:ntile))
    s%vmax = sqrt(vmax)
    s%w_gravity = s%w_gravity + sum(s%g%colour_sum(2, 1:ntile))
  end subroutine g2p_coloured

  !> G2P of particles k0..k1 (perm(k0..k1) when sorted); their kinetic energy and work of
  !! body forces in csum; with remap also m_p v_p phi into gmom.
  subroutine g2p_kernel(k0, k1, sorted, perm, np, nn, nb, nx, blk, w, vel, dvel, flip, dt, &
                        gravity, has_bacc, bacc, mass, v, x, remap, gmom, csum, vmax)
    integer, intent(in) :: k0, k1          !! range of particles (or of perm)
    logical, intent(in) :: sorted          !! particles are perm(k0..k1)
    integer, intent(in) :: np, nn, nb, nx  !! particles, nodes, block width, nodes along x
    integer, intent(in) :: perm(np)        !! particle order (sorted only)
    integer, intent(in) :: blk(2, np)      !! block origins
    real(wp), intent(in) :: w(nb*nb, np)   !! weights [-]
    real(wp), intent(in) :: vel(2, nn)     !! node velocity [m/s]
    real(wp), intent(in) :: dvel(2, nn)    !! node velocity change [m/s]
    real(wp), intent(in) :: flip           !! FLIP fraction [-]
    real(wp), intent(in) :: dt             !! time step [s]
    real(wp), intent(in) :: gravity(2)     !! gravity [m/s^2]
    logical, intent(in) :: has_bacc        !! per-particle body acceleration given
    real(wp), intent(in), allocatable :: bacc(:,:)  !! body acceleration (2, np) [m/s^2]
    real(wp), intent(in) :: mass(np)       !! particle mass [kg/m]
    real(wp), intent(inout) :: v(2, np)    !! particle velocity [m/s]
    real(wp), intent(inout) :: x(2, np)    !! particle position [m]
    logical, intent(in) :: remap           !! map the new momenta
    real(wp), intent(inout) :: gmom(2, nn) !! node momentum [kg/s]
    real(wp), intent(out) :: csum(2)       !! kinetic energy, body-force work [J/m]
    real(wp), intent(inout) :: vmax        !! largest squared speed [m^2/s^2]
    integer :: kp, ip, a, b, k, n
    real(wp) :: vpic(2), dv(2), vnew(2), fb(2), ekin, wgrav, wm
    ekin = 0.0_wp
    wgrav = 0.0_wp
    do kp = k0, k1
      ip = kp
      if (sorted) ip = perm(kp)
      vpic = 0.0_wp
      dv = 0.0_wp
      do b = 0, nb - 1
        n = 1 + blk(1, ip) + nx*(blk(2, ip) + b)
        do a = 0, nb - 1
          k = 1 + a + nb*b
          vpic = vpic + w(k, ip)*vel(:, n + a)
          dv = dv + w(k, ip)*dvel(:, n + a)
        end do
      end do
      vnew = flip*(v(:, ip) + dv) + (1.0_wp - flip)*vpic
      fb = gravity
      if (has_bacc) fb = fb + bacc(:, ip)
      wgrav = wgrav + mass(ip)*dot_product(fb, 0.5_wp*(v(:, ip) + vnew))*dt
      v(:, ip) = vnew
      x(:, ip) = x(:, ip) + dt*vpic
      ekin = ekin + 0.5_wp*mass(ip)*dot_product(vnew, vnew)
      vmax = max(vmax, dot_product(vnew, vnew))
      if (remap) then
        do b = 0, nb - 1
          n = 1 + blk(1, ip) + nx*(blk(2, ip) + b)
          do a = 0, nb - 1
            wm = w(1 + a + nb*b, ip)*mass(ip)
            gmom(1, n + a) = gmom(1, n + a) + wm*vnew(1)
            gmom(2, n + a) = gmom(2, n + a) + wm*vnew(2)
          end do
        end do
      end if
    end do
    csum = [ekin, wgrav]
  end subroutine g2p_kernel

  !> Step 6: L = sum v_i (x) grad phi, F <- (I + dt L) F, V = det(F) V0, stress update;
  !! accumulates plastic dissipation and the stored elastic energy; stops on det F <= 0,
  !! non-finite values or a failed return mapping.
  subroutine update_deformation(s, dt, stat, errmsg)
    type(sim_t), intent(inout) :: s        !! simulation
    real(wp), intent(in) :: dt             !! time step [s]
    integer, intent(out) :: stat           !! 0 or EXIT_NUMERIC
    character(len=:), allocatable, intent(inout) :: errmsg  !! what failed (set on failure)
    integer :: ic, bad(3), nchunk
    bad = 0
    stat = 0
    nchunk = (s%p%np + chunk - 1)/chunk
    !$omp parallel do default(none) schedule(static) shared(s, dt, nchunk) private(ic) &
    !$omp   reduction(max: bad) if(s%par)
    do ic = 1, nchunk
      call deformation_kernel(1 + (ic - 1)*chunk, min(ic*chunk, s%p%np), s%p%np, s%g%nn, &
             s%nb, s%g%nx, s%blk, s%gw, s%g%vel, dt, s%mats, s%plane, s%p%mat, s%p%vol0, &
             s%p%v, s%p%F, s%p%vol, s%p%stress, s%p%eqps, s%p%wplastic, s%chunk_sum(:, ic), bad)
    end do
    !$omp end parallel do
    s%e_plastic = s%e_plastic + sum(s%chunk_sum(1, 1:nchunk))
    s%e_strain = sum(s%chunk_sum(2, 1:nchunk))
    if (bad(1) > 0) then
      stat = EXIT_NUMERIC
      errmsg = 'det F <= 0 (inverted material) at particle '//itoa(bad(1))//' at ('// &
        rtoa(s%p%x(1, bad(1)))//', '//rtoa(s%p%x(2, bad(1)))//') m, '//step_context(s)// &
        '. Remedy: a smaller cfl, a finer grid (h below the wall thickness), or another '// &
        'basis (cpdi2 is the most robust)'
    else if (bad(2) > 0) then
      stat = EXIT_NUMERIC
      errmsg = 'the stress update did not converge at particle '//itoa(bad(2))//' at ('// &
        rtoa(s%p%x(1, bad(2)))//', '//rtoa(s%p%x(2, bad(2)))//') m, '//step_context(s)// &
        '. Remedy: a smaller cfl or dt'
    else if (bad(3) > 0) then
      stat = EXIT_NUMERIC
      errmsg = 'non-finite stress or velocity at particle '//itoa(bad(3))//', '// &
        step_context(s)//'. Remedy: a smaller cfl or dt (the time step is probably above '// &
        'the stable limit)'
    end if
  end subroutine update_deformation

  !> Deformation and stress of particles ip0..ip1 (one chunk); the chunk's plastic dissipation
  !! and stored elastic energy go to csum; bad(1:3) = largest particle with det F <= 0, a
  !! failed stress update, a non-finite result.
  subroutine deformation_kernel(ip0, ip1, np, nn, nb, nx, blk, gw, vel, dt, mats, plane, mat, &
                                vol0, v, F, vol, stress, eqps, wplastic, csum, bad)
    integer, intent(in) :: ip0, ip1        !! particles
    integer, intent(in) :: np, nn, nb, nx  !! particles, nodes, block width, nodes along x
    integer, intent(in) :: blk(2, np)      !! block origins
    real(wp), intent(in) :: gw(2, nb*nb, np)  !! gradients [1/m]
    real(wp), intent(in) :: vel(2, nn)     !! node velocity [m/s]
    real(wp), intent(in) :: dt             !! time step [s]
    type(material_t), intent(in) :: mats(:)  !! materials
    integer, intent(in) :: plane           !! PLANE_* code
    integer, intent(in) :: mat(np)         !! material of each particle
    real(wp), intent(in) :: vol0(np)       !! initial area [m^2]
    real(wp), intent(in) :: v(2, np)       !! velocity [m/s]
    real(wp), intent(inout) :: F(2, 2, np) !! deformation gradient [-]
    real(wp), intent(inout) :: vol(np)     !! area [m^2]
    real(wp), intent(inout) :: stress(4, np)  !! Cauchy stress [Pa]
    real(wp), intent(inout) :: eqps(np)    !! equivalent plastic strain [-]
    real(wp), intent(inout) :: wplastic(np)  !! plastic work [J/m]
    real(wp), intent(out) :: csum(2)       !! plastic dissipation, elastic energy [J/m]
    integer, intent(inout) :: bad(3)       !! failing particles (see above)
    integer :: ip, a, b, k, n, mstat
    real(wp) :: L(2, 2), Fn(2, 2), J, dwp, vn(2)
    csum = 0.0_wp
    do ip = ip0, ip1
      L = 0.0_wp
      do b = 0, nb - 1
        n = 1 + blk(1, ip) + nx*(blk(2, ip) + b)
        do a = 0, nb - 1
          k = 1 + a + nb*b
          vn = vel(:, n + a)
          L(1, 1) = L(1, 1) + vn(1)*gw(1, k, ip)
          L(1, 2) = L(1, 2) + vn(1)*gw(2, k, ip)
          L(2, 1) = L(2, 1) + vn(2)*gw(1, k, ip)
          L(2, 2) = L(2, 2) + vn(2)*gw(2, k, ip)
        end do
      end do
      Fn(1, 1) = F(1, 1, ip) + dt*(L(1, 1)*F(1, 1, ip) + L(1, 2)*F(2, 1, ip))
      Fn(1, 2) = F(1, 2, ip) + dt*(L(1, 1)*F(1, 2, ip) + L(1, 2)*F(2, 2, ip))
      Fn(2, 1) = F(2, 1, ip) + dt*(L(2, 1)*F(1, 1, ip) + L(2, 2)*F(2, 1, ip))
      Fn(2, 2) = F(2, 2, ip) + dt*(L(2, 1)*F(1, 2, ip) + L(2, 2)*F(2, 2, ip))
      J = Fn(1, 1)*Fn(2, 2) - Fn(1, 2)*Fn(2, 1)
      if (.not. J > 0.0_wp) then               ! also catches NaN
        bad(1) = max(bad(1), ip)
        cycle
      end if
      F(:, :, ip) = Fn
      vol(ip) = J*vol0(ip)
      call material_stress_update(mats(mat(ip)), plane, L, dt, Fn, stress(:, ip), eqps(ip), &
                                  dwp, mstat)
      if (mstat /= 0) then
        bad(2) = max(bad(2), ip)
        cycle
      end if
      if (.not. (ieee_is_finite(stress(1, ip)) .and. ieee_is_finite(stress(2, ip)) &
                 .and. ieee_is_finite(stress(3, ip)) .and. ieee_is_finite(v(1, ip)) &
                 .and. ieee_is_finite(v(2, ip)))) then
        bad(3) = max(bad(3), ip)
        cycle
      end if
      wplastic(ip) = wplastic(ip) + vol(ip)*dwp
      csum(1) = csum(1) + vol(ip)*dwp
      csum(2) = csum(2) + vol(ip)*material_energy_density(mats(mat(ip)), plane, stress(:, ip), Fn)
    end do
  end subroutine deformation_kernel

  !> Step 6 (domains): CPDI2 corners move with the grid velocity and the particle sits at the
  !! domain's centroid; CPDI1 half-vectors follow F (computed where used).
  subroutine update_domains(s, dt)
    type(sim_t), intent(inout) :: s        !! simulation
    real(wp), intent(in) :: dt             !! time step [s]
    integer :: ic, nchunk
    real(wp) :: dev
    if (s%basis /= BASIS_CPDI2) return
    nchunk = (s%p%nc + chunk - 1)/chunk
    !$omp parallel do default(none) schedule(static) shared(s, dt, nchunk) private(ic) if(s%par)
    do ic = 1, nchunk
      call corners_kernel(1 + (ic - 1)*chunk, min(ic*chunk, s%p%nc), s%p%nc, s%g%nn, s%g%nx, &
                          s%g%origin, s%g%h, s%g%vel, dt, s%p%xc)
    end do
    !$omp end parallel do
    dev = 0.0_wp
    nchunk = (s%p%np + chunk - 1)/chunk
    !$omp parallel do default(none) schedule(static) shared(s, nchunk) private(ic) &
    !$omp   reduction(max: dev) if(s%par)
    do ic = 1, nchunk
      call centroids_kernel(1 + (ic - 1)*chunk, min(ic*chunk, s%p%np), s%p%np, s%p%nc, &
                            s%p%corner, s%p%xc, s%p%vol, s%p%x, dev)
    end do
    !$omp end parallel do
    s%area_dev = max(s%area_dev, dev)
  end subroutine update_domains

  !> Corners ic0..ic1 move with the bilinear interpolant of the node velocity.
  subroutine corners_kernel(ic0, ic1, nc, nn, nx, origin, h, vel, dt, xc)
    integer, intent(in) :: ic0, ic1        !! corners
    integer, intent(in) :: nc, nn, nx      !! corners, nodes, nodes along x
    real(wp), intent(in) :: origin(2)      !! grid origin [m]
    real(wp), intent(in) :: h              !! cell size [m]
    real(wp), intent(in) :: vel(2, nn)     !! node velocity [m/s]
    real(wp), intent(in) :: dt             !! time step [s]
    real(wp), intent(inout) :: xc(2, nc)   !! corner positions [m]
    integer :: ic, i0, j0, n
    real(wp) :: w4(4), v(2)
    do ic = ic0, ic1
      call bilinear_at(xc(:, ic), origin, h, i0, j0, w4)
      n = 1 + i0 + nx*j0
      v = w4(1)*vel(:, n) + w4(2)*vel(:, n + 1) + w4(3)*vel(:, n + nx) + w4(4)*vel(:, n + nx + 1)
      xc(:, ic) = xc(:, ic) + dt*v
    end do
  end subroutine corners_kernel

  !> Particles ip0..ip1 sit at their domains' centroids; dev = largest |area / V - 1|.
  subroutine centroids_kernel(ip0, ip1, np, nc, corner, xc, vol, x, dev)
    integer, intent(in) :: ip0, ip1        !! particles
    integer, intent(in) :: np, nc          !! particles, corners
    integer, intent(in) :: corner(4, np)   !! corner ids
    real(wp), intent(in) :: xc(2, nc)      !! corner positions [m]
    real(wp), intent(in) :: vol(np)        !! particle area J V0 [m^2]
    real(wp), intent(inout) :: x(2, np)    !! positions [m]
    real(wp), intent(inout) :: dev         !! largest relative area deviation [-]
    integer :: ip
    real(wp) :: xq(2, 4), area, cen(2)
    do ip = ip0, ip1
      xq(:, 1) = xc(:, corner(1, ip))
      xq(:, 2) = xc(:, corner(2, ip))
      xq(:, 3) = xc(:, corner(3, ip))
      xq(:, 4) = xc(:, corner(4, ip))
      call quad_area_centroid(xq, area, cen)
      x(:, ip) = cen
      dev = max(dev, abs(area/vol(ip) - 1.0_wp))
    end do
  end subroutine centroids_kernel

end module mpm_solver
