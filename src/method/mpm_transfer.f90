!> Transfers between particles and grid (steps 2, 4 and 5 of docs/method.md): P2G of mass,
!! momentum and forces, G2P (FLIP/PIC blend, positions), and the MUSL re-map of the momenta.
! SPDX-License-Identifier: MIT
!
! Every transfer reuses the basis cache of step 1 (mpm_weights: block origin, weights and
! gradients of each particle). P2G accumulates per thread (thread 0 into the grid, the others
! into buffers added on the live tiles); with `deterministic` it is a four-colour sweep over the
! tiles instead (mpm_tiles), whose sums do not depend on the thread count. Particle sums
! (energies) are formed per fixed chunk of particles and added in order. The kernels take plain
! arrays: OpenMP clauses cannot name structure components (gfortran 12), and explicit-shape
! dummies keep the inner loops as fast as before.
module mpm_transfer
  !$ use omp_lib, only: omp_get_thread_num, omp_get_num_threads, omp_get_max_threads
  use mpm_kinds, only: wp, i8
  use mpm_particles, only: particles_t
  use mpm_grid, only: grid_t, buffers_t, grid_thread_buffers
  use mpm_tiles, only: tiles_t, tiles_span
  use mpm_state, only: params_t, state_t, work_t, chunk
  use mpm_constants, only: VOLUMETRIC_STANDARD
  use mpm_fbar, only: fbar_force_stress
  implicit none
  private
  public :: transfer_p2g, transfer_g2p, transfer_g2p_coloured

contains

  !> Step 2: P2G of mass and momentum (with the active-node cut-off) and/or of the forces.
  subroutine transfer_p2g(prm, p, g, tl, bf, wk, mass_momentum, force)
    type(params_t), intent(in) :: prm      !! parameters (gravity, body forces, sweep)
    type(particles_t), intent(in) :: p     !! particles
    type(grid_t), intent(inout) :: g       !! grid: mass, momentum, force
    type(tiles_t), intent(in) :: tl        !! live spans, colour groups
    type(buffers_t), intent(inout) :: bf   !! per-thread scatter buffers
    type(work_t), intent(inout) :: wk      !! basis cache (fbar: the forces' stress)
    logical, intent(in) :: mass_momentum   !! map mass and momentum
    logical, intent(in) :: force           !! map internal and body forces
    if (force .and. prm%volumetric /= VOLUMETRIC_STANDARD) then
      ! the forces see the averaged in-plane mean stress (mpm_fbar)
      call fbar_force_stress(p, g, wk, prm%volumetric)
      if (prm%deterministic) then
        call p2g_coloured(prm, p, g, tl, wk, wk%sforce, mass_momentum, force)
      else
        call p2g_threads(prm, p, g, tl, bf, wk, wk%sforce, mass_momentum, force)
      end if
    else if (prm%deterministic) then
      call p2g_coloured(prm, p, g, tl, wk, p%stress, mass_momentum, force)
    else
      call p2g_threads(prm, p, g, tl, bf, wk, p%stress, mass_momentum, force)
    end if
    if (mass_momentum) call set_mass_cut(g, tl, wk%par)
  end subroutine transfer_p2g

  !> P2G by per-thread accumulation: each thread maps a contiguous range of particles, thread 0
  !! into the grid and the others into their buffers, which are then added on the live tiles
  !! (and zeroed again).
  subroutine p2g_threads(prm, p, g, tl, bf, wk, stress, do_mass, do_force)
    type(params_t), intent(in) :: prm      !! parameters
    type(particles_t), intent(in) :: p     !! particles
    type(grid_t), intent(inout) :: g       !! grid
    type(tiles_t), intent(in) :: tl        !! live spans
    type(buffers_t), intent(inout) :: bf   !! per-thread scatter buffers
    type(work_t), intent(in) :: wk         !! basis cache
    real(wp), intent(in) :: stress(4, p%np)  !! the stress of the internal forces [Pa]
    logical, intent(in) :: do_mass, do_force  !! map mass and momentum, forces
    integer :: it, nt, ip0, ip1, np, k
    logical :: has_bacc
    np = p%np
    has_bacc = allocated(prm%bacc)
    nt = 1
    !$ if (wk%par) nt = omp_get_max_threads()
    call grid_thread_buffers(bf, g%nn*g%nf, nt)
    !$omp parallel default(none) &
    !$omp   shared(prm, p, g, tl, bf, wk, stress, np, has_bacc, do_mass, do_force) &
    !$omp   private(it, nt, ip0, ip1, k) if(wk%par)
    it = 0
    nt = 1
    !$ it = omp_get_thread_num()
    !$ nt = omp_get_num_threads()
    ip0 = 1 + int(int(np, i8)*int(it, i8)/int(nt, i8))
    ip1 = int(int(np, i8)*int(it + 1, i8)/int(nt, i8))
    if (it == 0) then
      call p2g_kernel(ip0, ip1, .false., wk%perm, np, g%nn, g%nf, prm%field, wk%nb, g%nx, &
                      wk%blk, wk%w, wk%gw, p%mass, p%v, p%vol, stress, prm%gravity, &
                      has_bacc, prm%bacc, do_mass, do_force, g%mass, g%mom, g%force)
    else
      call p2g_kernel(ip0, ip1, .false., wk%perm, np, g%nn, g%nf, prm%field, wk%nb, g%nx, &
                      wk%blk, wk%w, wk%gw, p%mass, p%v, p%vol, stress, prm%gravity, &
                      has_bacc, prm%bacc, do_mass, do_force, bf%buf_mass(:, it), &
                      bf%buf_mom(:, :, it), bf%buf_force(:, :, it))
    end if
    if (nt > 1) then
      !$omp barrier
      !$omp do schedule(static)
      do k = 1, tl%nspan
        call add_buffers(g, tl, bf, k, nt - 1, do_mass, do_mass, do_force)
      end do
      !$omp end do
    end if
    !$omp end parallel
  end subroutine p2g_threads

  !> Deterministic P2G: the occupied tiles of one colour write disjoint node sets (blocks fit
  !! in two tiles), so each group (band, colour) is a parallel loop over its tiles straight into
  !! the grid; every node sums its particles in (group, tile, index) order whatever the thread
  !! count.
  subroutine p2g_coloured(prm, p, g, tl, wk, stress, do_mass, do_force)
    type(params_t), intent(in) :: prm      !! parameters
    type(particles_t), intent(in) :: p     !! particles
    type(grid_t), intent(inout) :: g       !! grid
    type(tiles_t), intent(in) :: tl        !! colour groups
    type(work_t), intent(in) :: wk         !! basis cache
    real(wp), intent(in) :: stress(4, p%np)  !! the stress of the internal forces [Pa]
    logical, intent(in) :: do_mass, do_force  !! map mass and momentum, forces
    integer :: i, k, t, np
    logical :: has_bacc
    np = p%np
    has_bacc = allocated(prm%bacc)
    !$omp parallel default(none) &
    !$omp   shared(prm, p, g, tl, wk, stress, np, has_bacc, do_mass, do_force) &
    !$omp   private(i, k, t) if(wk%par)
    do i = 1, tl%ngroup
      !$omp do schedule(dynamic, 2)
      do k = tl%group_start(i), tl%group_start(i + 1) - 1
        t = tl%colour_tiles(k)
        call p2g_kernel(tl%tile_start(t), tl%tile_start(t + 1) - 1, .true., wk%perm, np, &
                        g%nn, g%nf, prm%field, wk%nb, g%nx, wk%blk, wk%w, wk%gw, p%mass, p%v, &
                        p%vol, stress, prm%gravity, has_bacc, prm%bacc, do_mass, do_force, &
                        g%mass, g%mom, g%force)
      end do
      !$omp end do
    end do
    !$omp end parallel
  end subroutine p2g_coloured

  !> Scatter of particles k0..k1 (perm(k0..k1) when sorted): mass m_p phi, momentum
  !! m_p v_p phi, force -V sigma . grad phi + phi m_p (g + b_p) (docs/method.md, step 1),
  !! each particle into the nodes of its velocity field (fld, when nf > 1).
  subroutine p2g_kernel(k0, k1, sorted, perm, np, nn, nf, fld, nb, nx, blk, w, gw, mass, v, &
                        vol, stress, gravity, has_bacc, bacc, do_mass, do_force, &
                        gmass, gmom, gforce)
    integer, intent(in) :: k0, k1          !! range of particles (or of perm)
    logical, intent(in) :: sorted          !! particles are perm(k0..k1)
    integer, intent(in) :: np, nn, nb, nx  !! particles, nodes, block width, nodes along x
    integer, intent(in) :: nf              !! velocity fields
    integer, intent(in), allocatable :: fld(:)  !! field of each particle (nf > 1) (np)
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
    real(wp), intent(inout) :: gmass(nn*nf)   !! node mass [kg/m]
    real(wp), intent(inout) :: gmom(2, nn*nf) !! node momentum [kg/s]
    real(wp), intent(inout) :: gforce(2, nn*nf)  !! node force [N/m]
    integer :: k, ip, a, b, kk, n, off
    real(wp) :: wm, sxx, syy, sxy, vp, fb(2)
    logical :: body
    body = has_bacc .or. any(gravity /= 0.0_wp)
    off = 0
    do k = k0, k1
      ip = k
      if (sorted) ip = perm(k)
      if (nf > 1) off = nn*(fld(ip) - 1)
      if (do_mass) then
        do b = 0, nb - 1
          n = 1 + blk(1, ip) + nx*(blk(2, ip) + b) + off
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
        if (body) then
          fb = mass(ip)*gravity
          if (has_bacc) fb = fb + mass(ip)*bacc(:, ip)
          do b = 0, nb - 1
            n = 1 + blk(1, ip) + nx*(blk(2, ip) + b) + off
            do a = 0, nb - 1
              kk = 1 + a + nb*b
              gforce(1, n + a) = gforce(1, n + a) - (sxx*gw(1, kk, ip) + sxy*gw(2, kk, ip)) &
                                 + w(kk, ip)*fb(1)
              gforce(2, n + a) = gforce(2, n + a) - (sxy*gw(1, kk, ip) + syy*gw(2, kk, ip)) &
                                 + w(kk, ip)*fb(2)
            end do
          end do
        else                                 ! no body force: the internal force only
          do b = 0, nb - 1
            n = 1 + blk(1, ip) + nx*(blk(2, ip) + b) + off
            do a = 0, nb - 1
              kk = 1 + a + nb*b
              gforce(1, n + a) = gforce(1, n + a) - (sxx*gw(1, kk, ip) + sxy*gw(2, kk, ip))
              gforce(2, n + a) = gforce(2, n + a) - (sxy*gw(1, kk, ip) + syy*gw(2, kk, ip))
            end do
          end do
        end if
      end if
    end do
  end subroutine p2g_kernel

  !> Add the thread buffers 1..nbuf to the grid on live span k, and zero them there.
  subroutine add_buffers(g, tl, bf, k, nbuf, do_mass, do_mom, do_force)
    type(grid_t), intent(inout) :: g       !! grid
    type(tiles_t), intent(in) :: tl        !! live spans
    type(buffers_t), intent(inout) :: bf   !! per-thread scatter buffers
    integer, intent(in) :: k               !! span index
    integer, intent(in) :: nbuf            !! buffers in use
    logical, intent(in) :: do_mass, do_mom, do_force  !! fields mapped
    integer :: i0, i1, j0, j1, j, n0, n1, ib, f
    call tiles_span(tl, k, i0, i1, j0, j1)
    do ib = 1, nbuf
      do f = 0, g%nf - 1
        do j = j0, j1
          n0 = 1 + i0 + g%nx*j + f*g%nn
          n1 = 1 + i1 + g%nx*j + f*g%nn
          if (do_mass) then
            g%mass(n0:n1) = g%mass(n0:n1) + bf%buf_mass(n0:n1, ib)
            bf%buf_mass(n0:n1, ib) = 0.0_wp
          end if
          if (do_mom) then
            g%mom(:, n0:n1) = g%mom(:, n0:n1) + bf%buf_mom(:, n0:n1, ib)
            bf%buf_mom(:, n0:n1, ib) = 0.0_wp
          end if
          if (do_force) then
            g%force(:, n0:n1) = g%force(:, n0:n1) + bf%buf_force(:, n0:n1, ib)
            bf%buf_force(:, n0:n1, ib) = 0.0_wp
          end if
        end do
      end do
    end do
  end subroutine add_buffers

  !> Zero the node momentum on the live tiles (before the MUSL re-map).
  subroutine zero_momentum(g, tl, par)
    type(grid_t), intent(inout) :: g       !! grid
    type(tiles_t), intent(in) :: tl        !! live spans
    logical, intent(in) :: par             !! run in parallel
    integer :: k, i0, i1, j0, j1, j, f, n
    !$omp parallel do default(none) schedule(static) shared(g, tl) &
    !$omp   private(k, i0, i1, j0, j1, j, f, n) if(par)
    do k = 1, tl%nspan
      call tiles_span(tl, k, i0, i1, j0, j1)
      do f = 0, g%nf - 1
        do j = j0, j1
          do n = 1 + i0 + g%nx*j + f*g%nn, 1 + i1 + g%nx*j + f*g%nn
            g%mom(1, n) = 0.0_wp             ! (element by element: no memset call per node)
            g%mom(2, n) = 0.0_wp
          end do
        end do
      end do
    end do
    !$omp end parallel do
  end subroutine zero_momentum

  !> Active nodes: mass above 1e-12 of the largest (docs/method.md, step 1).
  subroutine set_mass_cut(g, tl, par)
    type(grid_t), intent(inout) :: g       !! grid
    type(tiles_t), intent(in) :: tl        !! live spans
    logical, intent(in) :: par             !! run in parallel
    integer :: k, i0, i1, j0, j1, j, f
    real(wp) :: mmax
    mmax = 0.0_wp
    !$omp parallel do default(none) schedule(static) shared(g, tl) &
    !$omp   private(k, i0, i1, j0, j1, j, f) reduction(max: mmax) if(par)
    do k = 1, tl%nspan
      call tiles_span(tl, k, i0, i1, j0, j1)
      do f = 0, g%nf - 1
        do j = j0, j1
          mmax = max(mmax, maxval(g%mass(1 + i0 + g%nx*j + f*g%nn:1 + i1 + g%nx*j + f*g%nn)))
        end do
      end do
    end do
    !$omp end parallel do
    g%mass_cut = 1.0e-12_wp*mmax
  end subroutine set_mass_cut

  !> Step 4: FLIP/PIC velocity blend and position update (docs/method.md, step 3); also the
  !! kinetic energy, the largest speed and the work of body forces. With remap (MUSL, not
  !! deterministic), the new momenta go straight back to the grid (step 5) in the same pass,
  !! accumulated per thread like p2g_threads.
  subroutine transfer_g2p(prm, st, g, tl, bf, wk, dt, remap)
    type(params_t), intent(in) :: prm      !! parameters (FLIP, gravity, body forces)
    type(state_t), intent(inout) :: st     !! particles moved; kinetic energy, speed, work
    type(grid_t), intent(inout) :: g       !! grid: velocities read, momentum re-mapped
    type(tiles_t), intent(in) :: tl        !! live spans
    type(buffers_t), intent(inout) :: bf   !! per-thread scatter buffers
    type(work_t), intent(inout) :: wk      !! basis cache, partial sums
    real(wp), intent(in) :: dt             !! time step [s]
    logical, intent(in) :: remap           !! also map the new momenta to the grid
    integer :: it, nt, c0, c1, c, k, nchunk, np
    real(wp) :: vmax
    logical :: has_bacc, damp
    has_bacc = allocated(prm%bacc)
    damp = prm%damping > 0.0_wp
    np = st%p%np
    nchunk = (np + chunk - 1)/chunk
    if (remap) then
      call zero_momentum(g, tl, wk%par)
      nt = 1
      !$ if (wk%par) nt = omp_get_max_threads()
      call grid_thread_buffers(bf, g%nn*g%nf, nt)
    end if
    vmax = 0.0_wp
    !$omp parallel default(none) &
    !$omp   shared(prm, st, g, tl, bf, wk, dt, remap, has_bacc, damp, nchunk, np) &
    !$omp   private(it, nt, c0, c1, c, k) reduction(max: vmax) if(wk%par)
    it = 0
    nt = 1
    !$ it = omp_get_thread_num()
    !$ nt = omp_get_num_threads()
    c0 = 1 + (nchunk*it)/nt
    c1 = (nchunk*(it + 1))/nt
    do c = c0, c1
      if (it == 0 .or. .not. remap) then
        call g2p_kernel(1 + (c - 1)*chunk, min(c*chunk, np), .false., wk%perm, np, g%nn, &
               g%nf, prm%field, wk%nb, g%nx, wk%blk, wk%w, g%vel, g%dvel, prm%flip, dt, &
               prm%gravity, has_bacc, prm%bacc, damp, wk%vdamp, st%p%mass, st%p%v, st%p%x, &
               remap, g%mom, wk%chunk_sum(:, c), vmax)
      else
        call g2p_kernel(1 + (c - 1)*chunk, min(c*chunk, np), .false., wk%perm, np, g%nn, &
               g%nf, prm%field, wk%nb, g%nx, wk%blk, wk%w, g%vel, g%dvel, prm%flip, dt, &
               prm%gravity, has_bacc, prm%bacc, damp, wk%vdamp, st%p%mass, st%p%v, st%p%x, &
               remap, bf%buf_mom(:, :, it), wk%chunk_sum(:, c), vmax)
      end if
    end do
    if (remap .and. nt > 1) then
      !$omp barrier
      !$omp do schedule(static)
      do k = 1, tl%nspan
        call add_buffers(g, tl, bf, k, nt - 1, .false., .true., .false.)
      end do
      !$omp end do
    end if
    !$omp end parallel
    st%e_kin = sum(wk%chunk_sum(1, 1:nchunk))
    st%vmax = sqrt(vmax)
    st%w_gravity = st%w_gravity + sum(wk%chunk_sum(2, 1:nchunk))
    st%e_damped = st%e_damped + sum(wk%chunk_sum(3, 1:nchunk))
  end subroutine transfer_g2p

  !> Deterministic G2P with the MUSL momentum map: the particles tile by tile, group by group
  !! like p2g_coloured (the gathers do not care about the order; the momenta go straight into
  !! the grid), with the energy sums per tile, added in the fixed tile order.
  subroutine transfer_g2p_coloured(prm, st, g, tl, wk, dt)
    type(params_t), intent(in) :: prm      !! parameters (FLIP, gravity, body forces)
    type(state_t), intent(inout) :: st     !! particles moved; kinetic energy, speed, work
    type(grid_t), intent(inout) :: g       !! grid: velocities read, momentum re-mapped
    type(tiles_t), intent(inout) :: tl     !! colour groups, partial sums per tile
    type(work_t), intent(in) :: wk         !! basis cache
    real(wp), intent(in) :: dt             !! time step [s]
    integer :: i, k, t, np, ntile
    real(wp) :: vmax
    logical :: has_bacc, damp
    has_bacc = allocated(prm%bacc)
    damp = prm%damping > 0.0_wp
    np = st%p%np
    call zero_momentum(g, tl, wk%par)
    vmax = 0.0_wp
    !$omp parallel default(none) shared(prm, st, g, tl, wk, dt, np, has_bacc, damp) &
    !$omp   private(i, k, t) &
    !$omp   reduction(max: vmax) if(wk%par)
    do i = 1, tl%ngroup
      !$omp do schedule(dynamic, 2)
      do k = tl%group_start(i), tl%group_start(i + 1) - 1
        t = tl%colour_tiles(k)
        call g2p_kernel(tl%tile_start(t), tl%tile_start(t + 1) - 1, .true., wk%perm, np, &
               g%nn, g%nf, prm%field, wk%nb, g%nx, wk%blk, wk%w, g%vel, g%dvel, prm%flip, dt, &
               prm%gravity, has_bacc, prm%bacc, damp, wk%vdamp, st%p%mass, st%p%v, st%p%x, &
               .true., g%mom, tl%colour_sum(:, k), vmax)
      end do
      !$omp end do
    end do
    !$omp end parallel
    ntile = tl%group_start(tl%ngroup + 1) - 1
    st%e_kin = sum(tl%colour_sum(1, 1:ntile))
    st%vmax = sqrt(vmax)
    st%w_gravity = st%w_gravity + sum(tl%colour_sum(2, 1:ntile))
    st%e_damped = st%e_damped + sum(tl%colour_sum(3, 1:ntile))
  end subroutine transfer_g2p_coloured

  !> G2P of particles k0..k1 (perm(k0..k1) when sorted); their kinetic energy and work of
  !! body forces in csum, and (damp) the kinetic energy the damping took from them: each
  !! particle's new velocity less the damping's share of its change, sum_i N_i vdamp_i,
  !! against the new velocity (docs/method.md, "Energies"); with remap also m_p v_p phi
  !! into gmom.
  subroutine g2p_kernel(k0, k1, sorted, perm, np, nn, nf, fld, nb, nx, blk, w, vel, dvel, &
                        flip, dt, gravity, has_bacc, bacc, damp, vdamp, mass, v, x, remap, gmom, &
                        csum, vmax)
    integer, intent(in) :: k0, k1          !! range of particles (or of perm)
    logical, intent(in) :: sorted          !! particles are perm(k0..k1)
    integer, intent(in) :: np, nn, nb, nx  !! particles, nodes, block width, nodes along x
    integer, intent(in) :: nf              !! velocity fields
    integer, intent(in), allocatable :: fld(:)  !! field of each particle (nf > 1) (np)
    integer, intent(in) :: perm(np)        !! particle order (sorted only)
    integer, intent(in) :: blk(2, np)      !! block origins
    real(wp), intent(in) :: w(nb*nb, np)   !! weights [-]
    real(wp), intent(in) :: vel(2, nn*nf)  !! node velocity [m/s]
    real(wp), intent(in) :: dvel(2, nn*nf) !! node velocity change [m/s]
    real(wp), intent(in) :: flip           !! FLIP fraction [-]
    real(wp), intent(in) :: dt             !! time step [s]
    real(wp), intent(in) :: gravity(2)     !! gravity [m/s^2]
    logical, intent(in) :: has_bacc        !! per-particle body acceleration given
    real(wp), intent(in), allocatable :: bacc(:,:)  !! body acceleration (2, np) [m/s^2]
    logical, intent(in) :: damp            !! damping on: vdamp is set
    real(wp), intent(in), allocatable :: vdamp(:,:)  !! damping's node velocity change
                                           !! (2, nn*nf) [m/s]
    real(wp), intent(in) :: mass(np)       !! particle mass [kg/m]
    real(wp), intent(inout) :: v(2, np)    !! particle velocity [m/s]
    real(wp), intent(inout) :: x(2, np)    !! particle position [m]
    logical, intent(in) :: remap           !! map the new momenta
    real(wp), intent(inout) :: gmom(2, nn*nf) !! node momentum [kg/s]
    real(wp), intent(out) :: csum(3)       !! kinetic energy, body-force work, damped [J/m]
    real(wp), intent(inout) :: vmax        !! largest squared speed [m^2/s^2]
    integer :: kp, ip, a, b, k, n, off
    real(wp) :: vpic(2), dv(2), vnew(2), fb(2), ekin, wgrav, wm, vd(2), edamp
    logical :: body
    body = has_bacc .or. any(gravity /= 0.0_wp)
    ekin = 0.0_wp
    wgrav = 0.0_wp
    edamp = 0.0_wp
    off = 0
    do kp = k0, k1
      ip = kp
      if (sorted) ip = perm(kp)
      if (nf > 1) off = nn*(fld(ip) - 1)
      vpic = 0.0_wp
      dv = 0.0_wp
      do b = 0, nb - 1
        n = 1 + blk(1, ip) + nx*(blk(2, ip) + b) + off
        do a = 0, nb - 1
          k = 1 + a + nb*b
          vpic = vpic + w(k, ip)*vel(:, n + a)
          dv = dv + w(k, ip)*dvel(:, n + a)
        end do
      end do
      vnew = flip*(v(:, ip) + dv) + (1.0_wp - flip)*vpic
      if (damp) then                         ! FLIP and PIC both carry sum_i N_i vdamp_i
        vd = 0.0_wp
        do b = 0, nb - 1
          n = 1 + blk(1, ip) + nx*(blk(2, ip) + b) + off
          do a = 0, nb - 1
            vd = vd + w(1 + a + nb*b, ip)*vdamp(:, n + a)
          end do
        end do
        edamp = edamp + 0.5_wp*mass(ip)*(dot_product(vnew - vd, vnew - vd) - &
                                         dot_product(vnew, vnew))
      end if
      if (body) then                         ! work of body forces (0 without)
        fb = gravity
        if (has_bacc) fb = fb + bacc(:, ip)
        wgrav = wgrav + mass(ip)*dot_product(fb, 0.5_wp*(v(:, ip) + vnew))*dt
      end if
      v(:, ip) = vnew
      x(:, ip) = x(:, ip) + dt*vpic
      ekin = ekin + 0.5_wp*mass(ip)*dot_product(vnew, vnew)
      vmax = max(vmax, dot_product(vnew, vnew))
      if (remap) then
        do b = 0, nb - 1
          n = 1 + blk(1, ip) + nx*(blk(2, ip) + b) + off
          do a = 0, nb - 1
            wm = w(1 + a + nb*b, ip)*mass(ip)
            gmom(1, n + a) = gmom(1, n + a) + wm*vnew(1)
            gmom(2, n + a) = gmom(2, n + a) + wm*vnew(2)
          end do
        end do
      end if
    end do
    csum = [ekin, wgrav, edamp]
  end subroutine g2p_kernel

end module mpm_transfer
