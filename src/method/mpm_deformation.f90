!> Deformation (step 6 of docs/method.md): velocity gradient, deformation gradient, volume
!! and stress of every particle (the material model is mpm_material), and the CPDI2 domains:
!! corners moved with the grid velocity, particles at their domains' centroids.
! SPDX-License-Identifier: MIT
!
! volumetric = 'fbar' (mpm_fbar): the stress update sees the F-bar rate, whose volume change is
! the average over the particle's neighbourhood; F and the particle's area keep its own.
module mpm_deformation
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use mpm_kinds, only: wp
  use mpm_constants, only: EXIT_NUMERIC, BASIS_CPDI2, VOLUMETRIC_STANDARD
  use mpm_particles, only: particles_t, quad_area_centroid
  use mpm_grid, only: grid_t
  use mpm_material, only: material_t, material_stress_update
  use mpm_basis, only: bilinear_at
  use mpm_fbar, only: fbar_volume_change, fbar_rate, fbar_velocity_gradient
  use mpm_state, only: params_t, state_t, work_t, diag_t, chunk, state_context
  use mpm_strings, only: itoa, rtoa
  implicit none
  private
  public :: deformation_update, domains_update

contains

  !> Step 6: L = sum v_i (x) grad phi, F <- (I + dt L) F, V = det(F) V0, stress update;
  !! accumulates plastic dissipation and the stored elastic energy; stops on det F <= 0,
  !! non-finite values or a failed return mapping.
  subroutine deformation_update(prm, st, g, wk, dt, stat, errmsg)
    type(params_t), intent(in) :: prm      !! parameters (materials, plane)
    type(state_t), intent(inout) :: st     !! particles; plastic and elastic energy
    type(grid_t), intent(in) :: g          !! grid velocities
    type(work_t), intent(inout) :: wk      !! basis cache, partial sums
    real(wp), intent(in) :: dt             !! time step [s]
    integer, intent(out) :: stat           !! 0 or EXIT_NUMERIC
    character(len=:), allocatable, intent(inout) :: errmsg  !! what failed (set on failure)
    integer :: ic, bad(3), nchunk
    logical :: fbar
    bad = 0
    stat = 0
    nchunk = (st%p%np + chunk - 1)/chunk
    fbar = prm%volumetric /= VOLUMETRIC_STANDARD
    if (fbar) then
      call fbar_volume_change(st%p, g, wk, dt, prm%volumetric)
    else if (.not. allocated(wk%dj)) then
      allocate(wk%dj(0), wk%djbar(0), wk%sforce(4, 0), wk%lgrad(2, 2, 0))   ! not used
    end if
    !$omp parallel do default(none) schedule(static) shared(prm, st, g, wk, dt, nchunk, fbar) &
    !$omp   private(ic) reduction(max: bad) if(wk%par)
    do ic = 1, nchunk
      call deformation_kernel(1 + (ic - 1)*chunk, min(ic*chunk, st%p%np), st%p%np, g%nn, &
             g%nf, prm%field, wk%nb, g%nx, wk%blk, wk%gw, g%vel, dt, prm%mats, prm%plane, &
             st%p%mat, st%p%vol0, fbar, size(wk%dj), wk%lgrad, wk%dj, wk%djbar, st%p%v, st%p%F, &
             st%p%vol, st%p%stress, st%p%eqps, st%p%wplastic, wk%chunk_sum(:, ic), bad)
    end do
    !$omp end parallel do
    st%e_plastic = st%e_plastic + sum(wk%chunk_sum(1, 1:nchunk))
    st%e_strain = sum(wk%chunk_sum(2, 1:nchunk))
    if (bad(1) > 0) then
      stat = EXIT_NUMERIC
      errmsg = 'det F <= 0 (inverted material) at particle '//itoa(bad(1))//' at ('// &
        rtoa(st%p%x(1, bad(1)))//', '//rtoa(st%p%x(2, bad(1)))//') m, '// &
        state_context(st, prm, g%h)// &
        '. Remedy: a smaller cfl, a finer grid (h below the wall thickness), or another '// &
        'basis (cpdi2 is the most robust)'
    else if (bad(2) > 0) then
      stat = EXIT_NUMERIC
      errmsg = 'the stress update did not converge at particle '//itoa(bad(2))//' at ('// &
        rtoa(st%p%x(1, bad(2)))//', '//rtoa(st%p%x(2, bad(2)))//') m, '// &
        state_context(st, prm, g%h)// &
        '. Remedy: a smaller cfl or dt'
    else if (bad(3) > 0) then
      stat = EXIT_NUMERIC
      errmsg = 'non-finite stress or velocity at particle '//itoa(bad(3))//', '// &
        state_context(st, prm, g%h)//'. Remedy: a smaller cfl or dt (the time step is '// &
        'probably above the stable limit)'
    end if
  end subroutine deformation_update

  !> Deformation and stress of particles ip0..ip1 (one chunk); the chunk's plastic dissipation
  !! and stored elastic energy go to csum; bad(1:3) = largest particle with det F <= 0, a
  !! failed stress update, a non-finite result.
  subroutine deformation_kernel(ip0, ip1, np, nn, nf, fld, nb, nx, blk, gw, vel, dt, mats, &
                                plane, mat, vol0, fbar, ndj, lgrad, dj, djbar, v, F, vol, &
                                stress, eqps, wplastic, csum, bad)
    integer, intent(in) :: ip0, ip1        !! particles
    integer, intent(in) :: np, nn, nb, nx  !! particles, nodes, block width, nodes along x
    integer, intent(in) :: nf              !! velocity fields
    integer, intent(in), allocatable :: fld(:)  !! field of each particle (nf > 1) (np)
    integer, intent(in) :: blk(2, np)      !! block origins
    real(wp), intent(in) :: gw(2, nb*nb, np)  !! gradients [1/m]
    real(wp), intent(in) :: vel(2, nn*nf)  !! node velocity [m/s]
    real(wp), intent(in) :: dt             !! time step [s]
    type(material_t), intent(in) :: mats(:)  !! materials
    integer, intent(in) :: plane           !! PLANE_* code
    integer, intent(in) :: mat(np)         !! material of each particle
    real(wp), intent(in) :: vol0(np)       !! initial area [m^2]
    logical, intent(in) :: fbar            !! the stress update sees the F-bar rate
    integer, intent(in) :: ndj             !! np with fbar, else 0
    real(wp), intent(in) :: lgrad(2, 2, ndj)  !! velocity gradient (fbar: computed already) [1/s]
    real(wp), intent(in) :: dj(ndj)        !! volume change over the step det(I + dt L) - 1 [-]
    real(wp), intent(in) :: djbar(ndj)     !! its average over the neighbourhood [-]
    real(wp), intent(in) :: v(2, np)       !! velocity [m/s]
    real(wp), intent(inout) :: F(2, 2, np) !! deformation gradient [-]
    real(wp), intent(inout) :: vol(np)     !! area [m^2]
    real(wp), intent(inout) :: stress(4, np)  !! Cauchy stress [Pa]
    real(wp), intent(inout) :: eqps(np)    !! equivalent plastic strain [-]
    real(wp), intent(inout) :: wplastic(np)  !! plastic work [J/m]
    real(wp), intent(out) :: csum(2)       !! plastic dissipation, elastic energy [J/m]
    integer, intent(inout) :: bad(3)       !! failing particles (see above)
    integer :: ip, mstat, off
    real(wp) :: L(2, 2), Fn(2, 2), J, dwp, wel
    csum = 0.0_wp
    off = 0
    do ip = ip0, ip1
      if (fbar) then                ! (fbar has one velocity field: mpm_config_check)
        L = lgrad(:, :, ip)
      else
        if (nf > 1) off = nn*(fld(ip) - 1)
        call fbar_velocity_gradient(nb, nx, blk(:, ip), gw(:, :, ip), nn, &
                                    vel(:, off + 1:off + nn), L)
      end if
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
      if (fbar) L = fbar_rate(L, dt, dj(ip), djbar(ip))   ! F and vol keep the particle's own
      call material_stress_update(mats(mat(ip)), plane, L, dt, Fn, stress(:, ip), eqps(ip), &
                                  dwp, mstat, wel)
      if (mstat /= 0) then
        bad(2) = max(bad(2), ip)
        cycle
      end if
      ! the stress is finite when the update succeeds (material_stress_update checks it)
      if (.not. (ieee_is_finite(v(1, ip)) .and. ieee_is_finite(v(2, ip)))) then
        bad(3) = max(bad(3), ip)
        cycle
      end if
      wplastic(ip) = wplastic(ip) + vol(ip)*dwp
      csum(1) = csum(1) + vol(ip)*dwp
      csum(2) = csum(2) + vol(ip)*wel
    end do
  end subroutine deformation_kernel

  !> Step 6 (domains): CPDI2 corners move with the grid velocity and the particle sits at the
  !! domain's centroid; CPDI1 half-vectors follow F (computed where used).
  subroutine domains_update(prm, p, g, wk, diag, dt)
    type(params_t), intent(in) :: prm      !! parameters (basis)
    type(particles_t), intent(inout) :: p  !! particles: corners and positions
    type(grid_t), intent(in) :: g          !! grid velocities
    type(work_t), intent(in) :: wk         !! (parallel or not)
    type(diag_t), intent(inout) :: diag    !! largest area deviation
    real(wp), intent(in) :: dt             !! time step [s]
    integer :: ic, nchunk
    real(wp) :: dev
    if (prm%basis /= BASIS_CPDI2) return
    nchunk = (p%nc + chunk - 1)/chunk
    !$omp parallel do default(none) schedule(static) shared(prm, p, g, dt, nchunk) private(ic) &
    !$omp   if(wk%par)
    do ic = 1, nchunk
      call corners_kernel(1 + (ic - 1)*chunk, min(ic*chunk, p%nc), p%nc, g%nn, g%nf, &
                          prm%corner_field, g%nx, g%origin, g%h, g%vel, dt, p%xc)
    end do
    !$omp end parallel do
    dev = 0.0_wp
    nchunk = (p%np + chunk - 1)/chunk
    !$omp parallel do default(none) schedule(static) shared(p, nchunk) private(ic) &
    !$omp   reduction(max: dev) if(wk%par)
    do ic = 1, nchunk
      call centroids_kernel(1 + (ic - 1)*chunk, min(ic*chunk, p%np), p%np, p%nc, &
                            p%corner, p%xc, p%vol, p%x, dev)
    end do
    !$omp end parallel do
    diag%area_dev = max(diag%area_dev, dev)
  end subroutine domains_update

  !> Corners ic0..ic1 move with the bilinear interpolant of the node velocity (of their own
  !! field, cfld, when nf > 1).
  subroutine corners_kernel(ic0, ic1, nc, nn, nf, cfld, nx, origin, h, vel, dt, xc)
    integer, intent(in) :: ic0, ic1        !! corners
    integer, intent(in) :: nc, nn, nx      !! corners, nodes, nodes along x
    integer, intent(in) :: nf              !! velocity fields
    integer, intent(in), allocatable :: cfld(:)  !! field of each corner (nf > 1) (nc)
    real(wp), intent(in) :: origin(2)      !! grid origin [m]
    real(wp), intent(in) :: h              !! cell size [m]
    real(wp), intent(in) :: vel(2, nn*nf)  !! node velocity [m/s]
    real(wp), intent(in) :: dt             !! time step [s]
    real(wp), intent(inout) :: xc(2, nc)   !! corner positions [m]
    integer :: ic, i0, j0, n
    real(wp) :: w4(4), v(2)
    do ic = ic0, ic1
      call bilinear_at(xc(:, ic), origin, h, i0, j0, w4)
      n = 1 + i0 + nx*j0
      if (nf > 1) n = n + nn*(cfld(ic) - 1)
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

end module mpm_deformation
