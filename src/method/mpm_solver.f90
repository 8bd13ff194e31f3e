!> One explicit MPM time step (docs/method.md), as a page of numbered calls that match
!! docs/method.md; the initial energies, the stable time step and the energy balance.
! SPDX-License-Identifier: MIT
!
! The phases live in their own modules and take only the parts of the simulation they use
! (mpm_state: parameters, state, grid, tiles, buffers, work arrays, diagnostics):
!   1. mpm_weights      basis: node block, weights and gradients of every particle
!      mpm_tiles        binning: live tiles (the grid region with material), colour groups
!   2. mpm_transfer     P2G: mass, momentum, internal and body forces
!   3. mpm_grid_update  grid update and damping; mpm_contact: the walls on it (reaction =
!                       momentum added / dt)
!      mpm_body_contact contact between bodies (several velocity fields: detected after the
!                       P2G of step 2, applied in steps 2 (USF), 3 and 5)
!   4. mpm_transfer     G2P: FLIP/PIC velocity blend, positions
!   5. mpm_transfer, mpm_grid_update   MUSL: momenta mapped back, walls re-applied
!   6. mpm_deformation  L, F, volume, stress; CPDI domains (corners, centroids)
!   7. here             time, wall reactions, energy balance and the growth check
! Everything is per unit depth inside; outputs scale by depth (and the sector factor).
!
! Performance (docs/performance.md): grid loops visit the live tiles only (mass, momentum and
! force are zero outside them), so no step touches the whole grid. Particle sums (energies)
! are formed per fixed chunk of particles, node sums (wall impulses, damping) per live span,
! and added in order, so they do not depend on the thread count either. Loops run in parallel
! only from params_t%parallel_min particles on. Every per-particle operation is the same, in
! the same order, as in the plain serial algorithm, so one-thread results are bit-identical to
! it. The only allocation in a step is errmsg = ''.
module mpm_solver
  use mpm_kinds, only: wp, i8
  use mpm_constants, only: EXIT_NUMERIC, SCHEME_USF, SCHEME_MUSL
  use mpm_particles, only: particles_memory_bytes
  use mpm_grid, only: grid_memory_bytes, buffers_memory_bytes
  use mpm_tiles, only: tiles_bin, tiles_memory_bytes
  use mpm_material, only: material_energy_density
  use mpm_state, only: sim_t, params_t, state_t, diag_t
  use mpm_weights, only: weights_compute
  use mpm_transfer, only: transfer_p2g, transfer_g2p, transfer_g2p_coloured
  use mpm_grid_update, only: grid_velocity_walls, grid_update_walls
  use mpm_contact, only: contact_begin_step, contact_reactions, contact_energy, contact_check, &
                         contact_step_energy
  use mpm_body_contact, only: body_contact_detect, body_contact_apply, body_contact_reactions, &
                              body_contact_loss
  use mpm_self_contact, only: self_contact_mark, self_contact_weld
  use mpm_deformation, only: deformation_update, domains_update
  use mpm_walls, only: wall_kinetic
  use mpm_timers, only: clock_seconds, PHASE_BASIS, PHASE_P2G, PHASE_GRID, PHASE_G2P, &
                        PHASE_REMAP, PHASE_STRESS, PHASE_CORNERS, PHASE_OTHER
  use mpm_strings, only: itoa, rtoa
  use mpm_time_step, only: time_step_dt
  implicit none
  private
  public :: sim_t, solver_step, solver_stable_dt, solver_energies, solver_init_energy, &
            solver_memory_bytes

contains

  !> The time step at the run's cfl, mpm_time_step's cfl h / (c_d + max particle speed) [s].
  pure function solver_stable_dt(s) result(dt)
    type(sim_t), intent(in) :: s           !! simulation
    real(wp) :: dt
    dt = time_step_dt(s%prm%cfl, s%g%h, s%prm%c_max, s%vmax)
  end function solver_stable_dt

  !> Kinetic and stored elastic energy of the particles now [J/m].
  subroutine solver_energies(prm, st, ekin, estrain)
    type(params_t), intent(in) :: prm      !! parameters (materials, plane)
    type(state_t), intent(in) :: st        !! state (particles)
    real(wp), intent(out) :: ekin          !! kinetic energy [J/m]
    real(wp), intent(out) :: estrain       !! stored elastic energy [J/m]
    integer :: ip
    ekin = 0.0_wp
    estrain = 0.0_wp
    do ip = 1, st%p%np
      ekin = ekin + 0.5_wp*st%p%mass(ip)*dot_product(st%p%v(:, ip), st%p%v(:, ip))
      estrain = estrain + st%p%vol(ip)*material_energy_density(prm%mats(st%p%mat(ip)), &
                prm%plane, st%p%stress(:, ip), st%p%F(:, :, ip))
    end do
  end subroutine solver_energies

  !> Set the energies, E0 and the energy floor of the growth check from the initial state
  !! (walls and particles must be in place).
  subroutine solver_init_energy(s)
    type(sim_t), intent(inout) :: s        !! simulation
    integer :: ip, k
    real(wp) :: vwall, f
    call solver_energies(s%prm, s%state_t, s%e_kin, s%e_strain)
    call contact_energy(s%prm, s%state_t, s%g, s%wk)
    s%e0 = s%e_kin + s%e_strain + s%e_contact
    do k = 1, s%nwall
      if (s%walls(k)%mass > 0.0_wp) s%e0 = s%e0 + wall_kinetic(s%walls(k))
    end do
    vwall = 0.0_wp
    do k = 1, s%nwall
      f = 1.0_wp
      if (s%walls(k)%n_motion > 0) f = maxval(abs(s%walls(k)%motion_f(1:s%walls(k)%n_motion)))
      vwall = max(vwall, f*sqrt(dot_product(s%walls(k)%velocity, s%walls(k)%velocity)))
    end do
    s%prm%e_floor = 0.5_wp*sum(s%p%mass(1:s%p%np))*vwall**2
    s%vmax = 0.0_wp
    do ip = 1, s%p%np
      s%vmax = max(s%vmax, sqrt(dot_product(s%p%v(:, ip), s%p%v(:, ip))))
    end do
  end subroutine solver_init_energy

  !> Memory held by the simulation: particles, basis cache, work arrays, grid, tiles and
  !! thread buffers [bytes].
  function solver_memory_bytes(s) result(b)
    type(sim_t), intent(in) :: s           !! simulation
    integer(i8) :: b
    b = particles_memory_bytes(s%p) + grid_memory_bytes(s%g) &
        + tiles_memory_bytes(s%tiles) + buffers_memory_bytes(s%bufs)
    associate (wk => s%wk)
      if (allocated(wk%w)) b = b + 8_i8*(size(wk%w, kind=i8) + size(wk%gw, kind=i8)) &
                               + 4_i8*size(wk%blk, kind=i8)
      if (allocated(wk%tile)) b = b + 4_i8*(size(wk%tile, kind=i8) + size(wk%perm, kind=i8)) &
                                  + 8_i8*size(wk%chunk_sum, kind=i8)
      if (allocated(wk%dj)) b = b + 8_i8*(size(wk%dj, kind=i8) + size(wk%djbar, kind=i8))
      if (allocated(wk%sforce)) b = b + 8_i8*size(wk%sforce, kind=i8)
      if (allocated(wk%lgrad)) b = b + 8_i8*size(wk%lgrad, kind=i8)
      if (allocated(wk%node_sum)) b = b + 8_i8*size(wk%node_sum, kind=i8)
    end associate
    if (allocated(s%prm%bacc)) b = b + 8_i8*size(s%prm%bacc, kind=i8)
  end function solver_memory_bytes

  !> Advance by one time step (clipped to end exactly at t_end).
  !! stat = EXIT_NUMERIC with a message naming what failed, where and the remedy.
  subroutine solver_step(s, stat, errmsg)
    type(sim_t), intent(inout) :: s        !! simulation
    integer, intent(out) :: stat           !! 0 or EXIT_NUMERIC
    character(len=:), allocatable, intent(out) :: errmsg  !! what failed
    real(wp) :: dt, clock
    logical :: remap
    stat = 0
    errmsg = ''
    clock = clock_seconds()
    ! 0. time step; the walls at time t
    call time_step(s%prm, s%state_t, s%g%h, dt, stat, errmsg)
    if (stat /= 0) return
    s%dt = dt
    call contact_begin_step(s%state_t)
    s%wk%par = s%p%np >= s%prm%parallel_min
    call tick(s%diag, PHASE_OTHER, clock)
    ! 1. basis: weights and gradients once per step, reused by every transfer; tiles
    call weights_compute(s%prm, s%state_t, s%g, s%wk, s%diag, stat, errmsg)
    if (stat /= 0) return
    call tiles_bin(s%tiles, s%g, s%p%np, s%wk%nb, s%wk%blk, s%prm%deterministic, &
                   s%prm%colour_band, 1 + 2*s%nwall, s%wk%par, s%wk%tile, s%wk%perm)
    call tick(s%diag, PHASE_BASIS, clock)
    ! 2. P2G (USF: stress first, from the velocity mapped at the start of the step)
    if (s%prm%scheme == SCHEME_USF) then
      call transfer_p2g(s%prm, s%p, s%g, s%tiles, s%bufs, s%wk, mass_momentum=.true., &
                        force=.false.)
      call body_contact_detect(s%prm, s%state_t, s%g, s%tiles, s%wk)
      call self_contact_detect(s)
      call grid_velocity_walls(s%state_t, s%g, s%tiles, s%wk, dt)
      call body_contact_apply(s%prm, s%g, s%wk, dt, record=.false.)
      if (allocated(s%prm%self_bond)) call self_contact_weld(s%g, s%wk%sw, record=.false.)
      call tick(s%diag, PHASE_P2G, clock)
      call deformation_update(s%prm, s%state_t, s%g, s%wk, dt, stat, errmsg)
      if (stat /= 0) return
      call tick(s%diag, PHASE_STRESS, clock)
      call transfer_p2g(s%prm, s%p, s%g, s%tiles, s%bufs, s%wk, mass_momentum=.false., &
                        force=.true.)
    else                                     ! the stress is the previous step's
      call transfer_p2g(s%prm, s%p, s%g, s%tiles, s%bufs, s%wk, mass_momentum=.true., &
                        force=.true.)
      call body_contact_detect(s%prm, s%state_t, s%g, s%tiles, s%wk)
      call self_contact_detect(s)
    end if
    call tick(s%diag, PHASE_P2G, clock)
    ! 3. grid update, damping and walls
    call grid_update_walls(s%prm, s%state_t, s%g, s%tiles, s%wk, dt)
    call body_contact_apply(s%prm, s%g, s%wk, dt, record=.true.)   ! between bodies
    if (allocated(s%prm%self_bond)) call self_contact_weld(s%g, s%wk%sw, record=.true.)
    call contact_check(s%state_t, s%wk, s%g%h, stat, errmsg)
    if (stat /= 0) return
    call tick(s%diag, PHASE_GRID, clock)
    ! 4. G2P (and 5. the MUSL momentum map in the same pass)
    remap = s%prm%scheme == SCHEME_MUSL
    if (remap .and. s%prm%deterministic) then
      call transfer_g2p_coloured(s%prm, s%state_t, s%g, s%tiles, s%wk, dt)
    else
      call transfer_g2p(s%prm, s%state_t, s%g, s%tiles, s%bufs, s%wk, dt, remap)
    end if
    call tick(s%diag, PHASE_G2P, clock)
    ! 5. MUSL: the new particle momenta back on the grid, walls re-applied
    if (remap) then
      call grid_velocity_walls(s%state_t, s%g, s%tiles, s%wk, dt)
      call body_contact_apply(s%prm, s%g, s%wk, dt, record=.false.)
      if (allocated(s%prm%self_bond)) call self_contact_weld(s%g, s%wk%sw, record=.false.)
      call tick(s%diag, PHASE_REMAP, clock)
    end if
    ! 6. deformation and stress (USF did it in step 2), then the particle domains
    if (s%prm%scheme /= SCHEME_USF) then
      call deformation_update(s%prm, s%state_t, s%g, s%wk, dt, stat, errmsg)
      if (stat /= 0) return
      call tick(s%diag, PHASE_STRESS, clock)
    end if
    call domains_update(s%prm, s%p, s%g, s%wk, s%diag, dt)
    call tick(s%diag, PHASE_CORNERS, clock)
    ! 7. time, wall forces and work, energy balance
    s%t = s%t + dt
    s%step = s%step + 1_i8
    call contact_step_energy(s%prm, s%state_t, s%g, s%wk, dt)
    call contact_reactions(s%state_t, dt, s%prm%gravity)
    call body_contact_reactions(s%prm, s%state_t, s%wk, dt)
    call body_contact_loss(s%prm, s%state_t, s%g, s%wk, dt)
    call energy_balance(s%prm, s%state_t, s%g%h, dt, stat, errmsg)
    call tick(s%diag, PHASE_OTHER, clock)
  end subroutine solver_step

  !> Self-contact (mpm_self_contact): after the detection between fields, the nodes where the
  !! halves of a ring with self-contact are welded.
  subroutine self_contact_detect(s)
    type(sim_t), intent(inout) :: s        !! simulation: the welded nodes
    if (.not. allocated(s%prm%self_bond)) return
    call self_contact_mark(s%prm%field, s%prm%self_bond, s%prm%field_body, s%wk%nb, s%wk%blk, &
                           s%wk%w, s%wk%gw, s%g, s%wk%fc, s%wk%sw)
  end subroutine self_contact_detect

  !> Step 0: the stable (or fixed) time step, clipped so that the run ends exactly at t_end.
  subroutine time_step(prm, st, h, dt, stat, errmsg)
    type(params_t), intent(in) :: prm      !! parameters (cfl, fixed dt, t_end, wave speed)
    type(state_t), intent(in) :: st        !! state (time, largest speed)
    real(wp), intent(in) :: h              !! cell size [m]
    real(wp), intent(out) :: dt            !! time step [s]
    integer, intent(out) :: stat           !! 0 or EXIT_NUMERIC
    character(len=:), allocatable, intent(inout) :: errmsg  !! what failed (set on failure)
    stat = 0
    if (prm%dt_fixed > 0.0_wp) then
      dt = prm%dt_fixed
    else
      dt = time_step_dt(prm%cfl, h, prm%c_max, st%vmax)
    end if
    if (st%t + 1.0001_wp*dt >= prm%t_end) dt = prm%t_end - st%t
    if (.not. dt > 0.0_wp) then
      stat = EXIT_NUMERIC
      errmsg = 'time step '//rtoa(dt)//' s is not positive at t = '//rtoa(st%t)// &
               ' s: particle speeds are not finite; lower cfl'
    end if
  end subroutine time_step

  !> Step 7: external work, the balance kin + strain + plastic + damped + contact (+ the walls'
  !! friction loss for the energy error of docs/output.md, not for the growth check) -
  !! external - E0, and the growth check (stat = EXIT_NUMERIC past step 10).
  subroutine energy_balance(prm, st, h, dt, stat, errmsg)
    type(params_t), intent(in) :: prm      !! parameters (tolerances, wave speed)
    type(state_t), intent(inout) :: st     !! state: energies and their extremes
    real(wp), intent(in) :: h              !! cell size [m]
    real(wp), intent(in) :: dt             !! the step just taken [s]
    integer, intent(out) :: stat           !! 0 or EXIT_NUMERIC
    character(len=:), allocatable, intent(inout) :: errmsg  !! what failed (set on failure)
    real(wp) :: emech, scale, excess
    integer :: k
    stat = 0
    ! a wall with mass is part of the system: its kinetic energy counts, gravity's work on it
    ! is external, and its work on the material is internal
    st%e_external = st%w_gravity
    emech = st%e_kin + st%e_strain + st%e_plastic + st%e_damped + st%e_contact
    do k = 1, st%nwall
      if (st%walls(k)%mass > 0.0_wp) then
        st%e_external = st%e_external + st%walls(k)%w_gravity
        emech = emech + wall_kinetic(st%walls(k))
      else
        st%e_external = st%e_external + st%walls(k)%work
      end if
    end do
    ! energy_error as docs/output.md defines it: the largest imbalance over the run divided by
    ! max(E0, the largest external work), both maxima over the run so far; with the walls'
    ! friction loss, which the growth check below leaves out: friction only takes energy
    ! (docs/method.md, "Energies"), and its loss must not stop a run
    excess = emech - st%e_external - st%e0
    st%bal_max = max(st%bal_max, abs(excess + st%e_contact_loss))
    st%ext_max = max(st%ext_max, abs(st%e_external))
    scale = max(st%e0, st%ext_max, tiny(1.0_wp))
    ! with no energy at all yet (a body at rest before a wall's first impulse is counted) the
    ! ratio is undefined: it waits for a scale (bal/tiny would overflow)
    if (st%bal_max*epsilon(1.0_wp) < scale) st%energy_error = st%bal_max/scale
    if (st%step > 10_i8 .and. (excess > prm%energy_tol*scale .or. &
                               excess > prm%growth_tol*max(scale, prm%e_floor))) then
      stat = EXIT_NUMERIC
      errmsg = 'energy growth (instability) at step '//itoa(st%step)//', t = '//rtoa(st%t)// &
        ' s: kinetic + elastic + plastic + damped energy exceeds the initial energy plus the '// &
        'work put in by '//growth_text(excess, max(scale, prm%e_floor))//' (runs below the stable time '// &
        'step lose energy or gain a few %). The time step dt = '//rtoa(dt)//' s (cfl = '// &
        rtoa(dt*(prm%c_max + st%vmax)/h)//') is probably above the stable limit of this '// &
        'basis and scheme (docs/stability.md): lower cfl (0.1 to 0.3) or dt'
    end if
  end subroutine energy_balance

  !> The growth as a percentage of the energy scale, or in J/m while there is none.
  function growth_text(excess, scale) result(text)
    real(wp), intent(in) :: excess         !! energy gained [J/m]
    real(wp), intent(in) :: scale          !! energy scale [J/m]
    character(len=:), allocatable :: text
    if (excess*epsilon(1.0_wp) < scale) then
      text = rtoa(100.0_wp*excess/scale)//' %'
    else
      text = rtoa(excess)//' J/m (before any energy or work to compare it with)'
    end if
  end function growth_text

  !> Add the time since `clock` to phase `phase`; clock becomes now.
  subroutine tick(diag, phase, clock)
    type(diag_t), intent(inout) :: diag    !! diagnostics (phase times)
    integer, intent(in) :: phase           !! PHASE_* code
    real(wp), intent(inout) :: clock       !! last reading [s]
    real(wp) :: now
    now = clock_seconds()
    diag%phase_time(phase) = diag%phase_time(phase) + (now - clock)
    clock = now
  end subroutine tick
end module mpm_solver
