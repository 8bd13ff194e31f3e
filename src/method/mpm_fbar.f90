!> volumetric = 'fbar': the F-bar treatment of volumetric locking (docs/method.md, Volumetric
!! locking). The volume change of each particle over a step is averaged over the particles that
!! share its nodes, the stress update sees the step's deformation increment scaled to that
!! average (the F-bar rate), and the internal forces see the in-plane mean stress averaged the
!! same way (so that the forces do the work the material stores: the energy balance holds).
!! volumetric = 'fbarwall': the same F-bar, with the average replaced by the least-squares
!! linear fit through the wall (a ring's column of particles), which keeps what varies
!! linearly through the wall (the volume change of bending) and removes the rest.
! SPDX-License-Identifier: MIT
!
! The average of a particle quantity q (volume change, mean stress) is a node average mapped
! back with the particle's weights:
!   node i:     Q_i = sum_p phi_ip V_p q_p / sum_p phi_ip V_p
!   particle p: qbar_p = sum_i phi_ip Q_i
! with the step's weights phi (the basis cache) and the areas V at the start of the step. A
! uniform q is kept (partition of unity), the V-weighted sum of q is kept, and the operator is
! self-adjoint: sum_p V_p a_p bbar_p = sum_p V_p abar_p b_p, which makes the averaged mean stress
! of the forces the work-conjugate of the averaged volume change of the stress update. The node
! sums are serial, in particle order (the results do not depend on the thread count); the
! particle loops run in parallel.
!
! 'fbarwall': a ring's particles form columns through the wall (the domains joined across their
! edges (corner 2, corner 3) and (corner 1, corner 4), mpm_particles' ring_fill), layer l = 1
! (inner) to n_thick. Over each column the V-weighted least-squares line in l,
!   qbar_p = mean + slope (l_p - lbar),  mean, lbar V-weighted means,
!   slope = sum V q (l - lbar) / sum V (l - lbar)^2,
! is a V-weighted orthogonal projection: self-adjoint (the forces' mean stress is projected the
! same way), a uniform and a linear q are kept, and the V-weighted sum of q is kept. Serial.
module mpm_fbar
  use mpm_kinds, only: wp
  use mpm_particles, only: particles_t
  use mpm_grid, only: grid_t
  use mpm_state, only: work_t, chunk
  use mpm_constants, only: VOLUMETRIC_FBARWALL
  implicit none
  private
  public :: fbar_volume_change, fbar_force_stress, fbar_rate, fbar_velocity_gradient

contains

  !> Each particle's velocity gradient into wk%lgrad, its volume change over the step,
  !! dj = det(I + dt L) - 1, into wk%dj, and its average over the neighbourhood into wk%djbar.
  subroutine fbar_volume_change(p, g, wk, dt, mode)
    type(particles_t), intent(in) :: p     !! particles (areas at the start of the step)
    type(grid_t), intent(in) :: g          !! grid velocities
    type(work_t), intent(inout) :: wk      !! basis cache; dj and the node sums
    real(wp), intent(in) :: dt             !! time step [s]
    integer, intent(in) :: mode            !! VOLUMETRIC_FBAR or VOLUMETRIC_FBARWALL
    integer :: ic, nchunk
    call fbar_allocate(wk, p%np, g%nn)
    nchunk = (p%np + chunk - 1)/chunk
    !$omp parallel do default(none) schedule(static) shared(p, g, wk, dt, nchunk) private(ic) &
    !$omp   if(wk%par)
    do ic = 1, nchunk
      call volume_change_kernel(1 + (ic - 1)*chunk, min(ic*chunk, p%np), p%np, g%nn, wk%nb, &
                                g%nx, wk%blk, wk%gw, g%vel, dt, wk%lgrad, wk%dj)
    end do
    !$omp end parallel do
    call average(p, g, wk, mode)
  end subroutine fbar_volume_change

  !> The stress the internal forces use, into wk%sforce: the particle's stress with its
  !! in-plane mean (sigma_xx + sigma_yy)/2 replaced by the average over the neighbourhood.
  subroutine fbar_force_stress(p, g, wk, mode)
    type(particles_t), intent(in) :: p     !! particles: stress, area
    type(grid_t), intent(in) :: g          !! grid (size)
    type(work_t), intent(inout) :: wk      !! basis cache; sforce (dj, djbar as scratch)
    integer, intent(in) :: mode            !! VOLUMETRIC_FBAR or VOLUMETRIC_FBARWALL
    integer :: ip
    call fbar_allocate(wk, p%np, g%nn)
    do ip = 1, p%np
      wk%dj(ip) = 0.5_wp*(p%stress(1, ip) + p%stress(2, ip))
    end do
    call average(p, g, wk, mode)
    do ip = 1, p%np
      wk%sforce(:, ip) = p%stress(:, ip)
      wk%sforce(1, ip) = p%stress(1, ip) + (wk%djbar(ip) - wk%dj(ip))
      wk%sforce(2, ip) = p%stress(2, ip) + (wk%djbar(ip) - wk%dj(ip))
    end do
  end subroutine fbar_force_stress

  !> wk%djbar = the average of the particle quantity wk%dj of the treatment mode: through the
  !! nodes ('fbar') or the line through the wall ('fbarwall'; module header).
  subroutine average(p, g, wk, mode)
    type(particles_t), intent(in) :: p     !! particles: areas, corners
    type(grid_t), intent(in) :: g          !! grid (size)
    type(work_t), intent(inout) :: wk      !! basis cache, node sums, columns; dj, djbar
    integer, intent(in) :: mode            !! VOLUMETRIC_FBAR or VOLUMETRIC_FBARWALL
    if (mode == VOLUMETRIC_FBARWALL) then
      if (.not. allocated(wk%column)) call wall_columns(p, wk%column)
      call column_fit(p%np, wk%column, p%vol, wk%dj, wk%djbar)
    else
      call node_average(p%np, g%nn, wk%nb, g%nx, wk%blk, wk%w, wk%par, p%vol, wk%dj, &
                        wk%node_sum, wk%djbar)
    end if
  end subroutine average

  !> Each particle's column through the wall and its layer in it (module header): the chains
  !! of domains joined across their edges (corner 2, corner 3) = the next one's (corner 1,
  !! corner 4), numbered from the domain with none before it (a ring's inner surface).
  subroutine wall_columns(p, column)
    type(particles_t), intent(in) :: p     !! particles: corner ids
    integer, allocatable, intent(out) :: column(:,:)  !! column and layer (2, np)
    integer, allocatable :: owner(:), next(:)
    logical, allocatable :: inner(:)
    integer :: ip, q, ncol, layer
    allocate(column(2, p%np), owner(p%nc), next(p%np), inner(p%np))
    owner = 0
    next = 0
    inner = .true.
    column = 0
    do ip = 1, p%np
      owner(p%corner(1, ip)) = ip
    end do
    do ip = 1, p%np
      q = owner(p%corner(2, ip))
      if (q == 0 .or. q == ip) cycle
      if (p%corner(4, q) /= p%corner(3, ip)) cycle
      next(ip) = q
      inner(q) = .false.
    end do
    ncol = 0
    do ip = 1, p%np
      if (.not. inner(ip)) cycle
      ncol = ncol + 1
      q = ip
      layer = 0
      do while (q /= 0)
        layer = layer + 1
        column(:, q) = [ncol, layer]
        q = next(q)
      end do
    end do
    do ip = 1, p%np                        ! (a closed chain: none in a ring; kept alone)
      if (column(1, ip) /= 0) cycle
      ncol = ncol + 1
      column(:, ip) = [ncol, 1]
    end do
  end subroutine wall_columns

  !> qbar = the V-weighted least-squares line in the layer over each column (module header);
  !! a column of one layer, or of one layer's worth of area, keeps its mean.
  subroutine column_fit(np, column, vol, q, qbar)
    integer, intent(in) :: np              !! particles
    integer, intent(in) :: column(2, np)   !! column and layer
    real(wp), intent(in) :: vol(np)        !! areas [m^2]
    real(wp), intent(in) :: q(np)          !! the quantity
    real(wp), intent(out) :: qbar(np)      !! its fit
    real(wp), allocatable :: c(:,:)
    integer :: ip, k
    real(wp) :: x, lbar, sxx, sxq
    allocate(c(5, maxval(column(1, :))))
    c = 0.0_wp
    do ip = 1, np
      k = column(1, ip)
      x = real(column(2, ip), wp)
      c(:, k) = c(:, k) + vol(ip)*[1.0_wp, x, x*x, q(ip), q(ip)*x]
    end do
    do ip = 1, np
      k = column(1, ip)
      x = real(column(2, ip), wp)
      lbar = c(2, k)/c(1, k)
      sxx = c(3, k) - lbar*c(2, k)        ! sum V (l - lbar)^2
      sxq = c(5, k) - lbar*c(4, k)        ! sum V q (l - lbar)
      qbar(ip) = c(4, k)/c(1, k)
      if (sxx > 1.0e-9_wp*c(1, k)) qbar(ip) = qbar(ip) + sxq/sxx*(x - lbar)
    end do
  end subroutine column_fit

  !> The F-bar rate: the rate Lbar whose increment I + dt Lbar is (dJbar / dJ)^(1/2) (I + dt L),
  !! with dJ = 1 + dj and dJbar = 1 + djbar (the in-plane increment of a plane-strain F-bar;
  !! F_zz = 1). Lbar = L when djbar = dj.
  pure function fbar_rate(L, dt, dj, djbar) result(Lbar)
    real(wp), intent(in) :: L(2, 2)        !! velocity gradient [1/s]
    real(wp), intent(in) :: dt             !! time step [s]
    real(wp), intent(in) :: dj             !! det(I + dt L) - 1 [-]
    real(wp), intent(in) :: djbar          !! its average over the neighbourhood [-]
    real(wp) :: Lbar(2, 2)
    real(wp) :: alpha, g
    alpha = sqrt((1.0_wp + djbar)/(1.0_wp + dj))
    ! (alpha - 1)/dt without the cancellation: alpha^2 - 1 = (djbar - dj)/(1 + dj)
    g = (djbar - dj)/((1.0_wp + dj)*(alpha + 1.0_wp)*dt)
    Lbar(1, 1) = L(1, 1) + g*(1.0_wp + dt*L(1, 1))
    Lbar(2, 1) = L(2, 1) + g*dt*L(2, 1)
    Lbar(1, 2) = L(1, 2) + g*dt*L(1, 2)
    Lbar(2, 2) = L(2, 2) + g*(1.0_wp + dt*L(2, 2))
  end function fbar_rate

  !> L = sum over the block of v_i (x) grad phi_i of one particle [1/s].
  pure subroutine fbar_velocity_gradient(nb, nx, blk, gw, nn, vel, L)
    integer, intent(in) :: nb, nx          !! block width, nodes along x
    integer, intent(in) :: blk(2)          !! block origin
    real(wp), intent(in) :: gw(2, nb*nb)   !! gradients [1/m]
    integer, intent(in) :: nn              !! nodes
    real(wp), intent(in) :: vel(2, nn)     !! node velocity [m/s]
    real(wp), intent(out) :: L(2, 2)       !! velocity gradient, L(i,j) = dv_i/dx_j [1/s]
    integer :: a, b, k, n
    real(wp) :: vn(2)
    L = 0.0_wp
    do b = 0, nb - 1
      n = 1 + blk(1) + nx*(blk(2) + b)
      do a = 0, nb - 1
        k = 1 + a + nb*b
        vn = vel(:, n + a)
        L(1, 1) = L(1, 1) + vn(1)*gw(1, k)
        L(1, 2) = L(1, 2) + vn(1)*gw(2, k)
        L(2, 1) = L(2, 1) + vn(2)*gw(1, k)
        L(2, 2) = L(2, 2) + vn(2)*gw(2, k)
      end do
    end do
  end subroutine fbar_velocity_gradient

  !> The work arrays of the F-bar for np particles and nn nodes (node sums zero).
  subroutine fbar_allocate(wk, np, nn)
    type(work_t), intent(inout) :: wk      !! work arrays
    integer, intent(in) :: np, nn          !! particles, nodes
    if (allocated(wk%dj)) then
      if (size(wk%dj) /= np) deallocate(wk%dj, wk%djbar, wk%sforce, wk%lgrad)
    end if
    if (.not. allocated(wk%dj)) allocate(wk%dj(np), wk%djbar(np), wk%sforce(4, np), &
                                         wk%lgrad(2, 2, np))
    if (allocated(wk%column)) then
      if (size(wk%column, 2) /= np) deallocate(wk%column)
    end if
    if (allocated(wk%node_sum)) then
      if (size(wk%node_sum, 2) /= nn) deallocate(wk%node_sum)
    end if
    if (.not. allocated(wk%node_sum)) then
      allocate(wk%node_sum(2, nn))
      wk%node_sum = 0.0_wp
    end if
  end subroutine fbar_allocate

  !> qbar = the node average of q mapped back (module header); node_sum is zero on entry and
  !! on return.
  subroutine node_average(np, nn, nb, nx, blk, w, par, vol, q, node_sum, qbar)
    integer, intent(in) :: np, nn, nb, nx  !! particles, nodes, block width, nodes along x
    integer, intent(in) :: blk(2, np)      !! block origins
    real(wp), intent(in) :: w(nb*nb, np)   !! weights [-]
    logical, intent(in) :: par             !! run the particle loop in parallel
    real(wp), intent(in) :: vol(np)        !! particle area [m^2]
    real(wp), intent(in) :: q(np)          !! the particle quantity
    real(wp), intent(inout) :: node_sum(2, nn)  !! node sums
    real(wp), intent(out) :: qbar(np)      !! its average
    integer :: ic, nchunk
    call node_scatter(np, nn, nb, nx, blk, w, vol, q, node_sum)
    nchunk = (np + chunk - 1)/chunk
    !$omp parallel do default(none) schedule(static) &
    !$omp   shared(nchunk, np, nn, nb, nx, blk, w, node_sum, qbar) private(ic) if(par)
    do ic = 1, nchunk
      call node_gather_kernel(1 + (ic - 1)*chunk, min(ic*chunk, np), np, nn, nb, nx, blk, w, &
                              node_sum, qbar)
    end do
    !$omp end parallel do
    call node_clear(np, nn, nb, nx, blk, node_sum)
  end subroutine node_average

  !> L and dj(ip) = det(I + dt L) - 1 of particles ip0..ip1.
  subroutine volume_change_kernel(ip0, ip1, np, nn, nb, nx, blk, gw, vel, dt, lgrad, dj)
    integer, intent(in) :: ip0, ip1        !! particles
    integer, intent(in) :: np, nn, nb, nx  !! particles, nodes, block width, nodes along x
    integer, intent(in) :: blk(2, np)      !! block origins
    real(wp), intent(in) :: gw(2, nb*nb, np)  !! gradients [1/m]
    real(wp), intent(in) :: vel(2, nn)     !! node velocity [m/s]
    real(wp), intent(in) :: dt             !! time step [s]
    real(wp), intent(inout) :: lgrad(2, 2, np)  !! velocity gradient [1/s]
    real(wp), intent(inout) :: dj(np)      !! volume change over the step [-]
    integer :: ip
    real(wp) :: L(2, 2)
    do ip = ip0, ip1
      call fbar_velocity_gradient(nb, nx, blk(:, ip), gw(:, :, ip), nn, vel, L)
      lgrad(:, :, ip) = L
      ! det(I + dt L) - 1 without the cancellation of the 1
      dj(ip) = dt*(L(1, 1) + L(2, 2)) + dt*dt*(L(1, 1)*L(2, 2) - L(1, 2)*L(2, 1))
    end do
  end subroutine volume_change_kernel

  !> Node sums of phi V q and phi V over all particles, in particle order; then each node's
  !! average into node_sum(1, :) (node_sum(2, :) back to zero), one division per node.
  subroutine node_scatter(np, nn, nb, nx, blk, w, vol, q, node_sum)
    integer, intent(in) :: np, nn, nb, nx  !! particles, nodes, block width, nodes along x
    integer, intent(in) :: blk(2, np)      !! block origins
    real(wp), intent(in) :: w(nb*nb, np)   !! weights [-]
    real(wp), intent(in) :: vol(np)        !! particle area [m^2]
    real(wp), intent(in) :: q(np)          !! the particle quantity
    real(wp), intent(inout) :: node_sum(2, nn)  !! node sums (zero on entry)
    integer :: ip, a, b, n
    real(wp) :: wv
    do ip = 1, np
      do b = 0, nb - 1
        n = 1 + blk(1, ip) + nx*(blk(2, ip) + b)
        do a = 0, nb - 1
          wv = w(1 + a + nb*b, ip)*vol(ip)
          node_sum(1, n + a) = node_sum(1, n + a) + wv*q(ip)
          node_sum(2, n + a) = node_sum(2, n + a) + wv
        end do
      end do
    end do
    do ip = 1, np
      do b = 0, nb - 1
        n = 1 + blk(1, ip) + nx*(blk(2, ip) + b)
        do a = n, n + nb - 1
          if (node_sum(2, a) /= 0.0_wp) then  ! (zero: no weight there, or averaged already)
            node_sum(1, a) = node_sum(1, a)/node_sum(2, a)
            node_sum(2, a) = 0.0_wp
          end if
        end do
      end do
    end do
  end subroutine node_scatter

  !> qbar(ip) = sum_i phi_ip Q_i of particles ip0..ip1 (Q_i = node_sum(1, i), node_scatter).
  subroutine node_gather_kernel(ip0, ip1, np, nn, nb, nx, blk, w, node_sum, qbar)
    integer, intent(in) :: ip0, ip1        !! particles
    integer, intent(in) :: np, nn, nb, nx  !! particles, nodes, block width, nodes along x
    integer, intent(in) :: blk(2, np)      !! block origins
    real(wp), intent(in) :: w(nb*nb, np)   !! weights [-]
    real(wp), intent(in) :: node_sum(2, nn)  !! node sums
    real(wp), intent(inout) :: qbar(np)    !! the average
    integer :: ip, a, b, n, k
    real(wp) :: s
    do ip = ip0, ip1
      s = 0.0_wp
      do b = 0, nb - 1
        n = 1 + blk(1, ip) + nx*(blk(2, ip) + b)
        do a = 0, nb - 1
          k = 1 + a + nb*b
          s = s + w(k, ip)*node_sum(1, n + a)
        end do
      end do
      qbar(ip) = s
    end do
  end subroutine node_gather_kernel

  !> Zero the node sums on the particles' blocks (all that node_scatter touched).
  subroutine node_clear(np, nn, nb, nx, blk, node_sum)
    integer, intent(in) :: np, nn, nb, nx  !! particles, nodes, block width, nodes along x
    integer, intent(in) :: blk(2, np)      !! block origins
    real(wp), intent(inout) :: node_sum(2, nn)  !! node sums
    integer :: ip, b, n
    do ip = 1, np
      do b = 0, nb - 1
        n = 1 + blk(1, ip) + nx*(blk(2, ip) + b)
        node_sum(:, n:n + nb - 1) = 0.0_wp
      end do
    end do
  end subroutine node_clear

end module mpm_fbar
