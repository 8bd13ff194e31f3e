!> Rigid-wall contact at the material surface: a kinematic constraint on surface points.
! SPDX-License-Identifier: MIT
!
! The material surface is a set of points x_c (the CPDI2 domain corners, or the corners of the
! CPDI1 parallelogram / uGIMP square of each particle). A point moves with the bilinear
! interpolant of the node velocities, v_c = sum_i N_i(x_c) v_i, exactly as the CPDI2 corners
! do. Against a wall with unit normal n (into the material), velocity v_w and a gap
! g_c = (x_c - x_w) . n at the start of the step, the constraint is
!
!     (v_c - v_w) . n >= -max(g_c, 0) / dt        (the point may close its gap, not cross)
!
! with an impulse lambda_c >= 0 along n (the wall pushes, never pulls: separation is free). The
! impulse goes to the nodes in proportion to N_i / m_i: dv_i = lambda N_i / m_i. This is the
! correction of least kinetic energy (mass-weighted least squares) that satisfies the
! constraint, and the momentum given to the nodes is lambda * sum_i N_i, summed into the wall
! reaction exactly. Friction adds a tangential impulse: 'stick' makes the tangential relative
! velocity zero, 'coulomb' bounds |lambda_t| by mu lambda_n. Points that share nodes are
! solved together by projected Gauss-Seidel sweeps, in a fixed order (results do not depend on
! the thread count). Only nodes with mass above the cut-off take part.
module mpm_surface_contact
  use mpm_kinds, only: wp
  use mpm_constants, only: CONTACT_COULOMB, CONTACT_STICK
  use mpm_basis, only: bilinear_at
  implicit none
  private
  public :: surface_work_t, surface_constrain

  integer, parameter :: max_sweeps = 200     !! Gauss-Seidel sweeps at most [-]
  real(wp), parameter :: sweep_tol = 1.0e-13_wp  !! relative change that ends the sweeps [-]

  !> Work arrays of the constraint solve, grown as needed (no allocation in a steady run).
  type :: surface_work_t
    integer, allocatable :: node(:,:)      !! the 4 nodes of each point's cell (4, n)
    real(wp), allocatable :: wt(:,:)       !! their weights N_i / m_i (4, n) [m/kg]
    real(wp), allocatable :: nw(:,:)       !! their weights N_i (4, n) [-]
    real(wp), allocatable :: s(:)          !! sum_i N_i^2 / m_i of each point [m/kg]
    real(wp), allocatable :: lam(:,:)      !! normal and tangential impulses (2, n) [kg/s]
    integer :: sweeps = 0                  !! sweeps taken by the last solve
  end type surface_work_t

contains

  !> Apply one wall to the surface points xs(:, 1:npt) (those within reach), whose gaps at the
  !! start of the step are gap(1:npt). Node velocities vel change in place; dvel (when
  !! add_dvel) gets the same change; impulse is the momentum given to the material.
  subroutine surface_constrain(npt, xs, gap, origin, h, nx, ny, mass, mass_cut, law, friction, &
                               normal, vwall, dt, add_dvel, vel, dvel, impulse, wk)
    integer, intent(in) :: npt             !! surface points
    real(wp), intent(in) :: xs(:,:)        !! their positions (2, >= npt) [m]
    real(wp), intent(in) :: gap(:)         !! their distances to the plane (>= npt) [m]
    real(wp), intent(in) :: origin(2)      !! position of node (0, 0) [m]
    real(wp), intent(in) :: h              !! cell size [m]
    integer, intent(in) :: nx, ny          !! nodes along x and y
    real(wp), intent(in) :: mass(:)        !! node mass [kg/m]
    real(wp), intent(in) :: mass_cut       !! active nodes have mass above this [kg/m]
    integer, intent(in) :: law             !! CONTACT_FRICTIONLESS, _COULOMB or _STICK
    real(wp), intent(in) :: friction       !! Coulomb coefficient [-]
    real(wp), intent(in) :: normal(2)      !! unit normal into the material [-]
    real(wp), intent(in) :: vwall(2)       !! wall velocity over the step [m/s]
    real(wp), intent(in) :: dt             !! time step [s]
    logical, intent(in) :: add_dvel        !! also add the change to dvel
    real(wp), intent(inout) :: vel(:,:)    !! node velocity (2, nn) [m/s]
    real(wp), intent(inout) :: dvel(:,:)   !! node velocity change of the step (2, nn) [m/s]
    real(wp), intent(out) :: impulse(2)    !! momentum given to the material [kg/s per m]
    type(surface_work_t), intent(inout) :: wk  !! work arrays
    integer :: c, k, n, i0, j0, sweep
    real(wp) :: w4(4), tang(2), vc(2), vrel(2), target, ln, lt, dln, dlt, change, vscale, d(2)
    impulse = 0.0_wp
    wk%sweeps = 0
    if (npt <= 0) return
    call grow(wk, npt)
    tang = [-normal(2), normal(1)]
    ! weights of each point; points outside the grid or on no active node are left out (s = 0)
    vscale = sqrt(dot_product(vwall, vwall))
    do c = 1, npt
      call bilinear_at(xs(:, c), origin, h, i0, j0, w4)
      wk%s(c) = 0.0_wp
      wk%lam(:, c) = 0.0_wp
      wk%node(:, c) = 0
      wk%wt(:, c) = 0.0_wp
      wk%nw(:, c) = 0.0_wp
      if (i0 < 0 .or. j0 < 0 .or. i0 + 1 > nx - 1 .or. j0 + 1 > ny - 1) cycle
      wk%node(:, c) = [1 + i0 + nx*j0, 2 + i0 + nx*j0, 1 + i0 + nx*(j0 + 1), 2 + i0 + nx*(j0 + 1)]
      do k = 1, 4
        n = wk%node(k, c)
        if (mass(n) > mass_cut) then
          wk%nw(k, c) = w4(k)
          wk%wt(k, c) = w4(k)/mass(n)
          wk%s(c) = wk%s(c) + w4(k)*w4(k)/mass(n)
          vscale = max(vscale, maxval(abs(vel(:, n))))
        end if
      end do
    end do
    vscale = max(vscale, tiny(1.0_wp))
    ! projected Gauss-Seidel over the points, in order
    do sweep = 1, max_sweeps
      change = 0.0_wp
      do c = 1, npt
        if (.not. wk%s(c) > 0.0_wp) cycle
        vc = 0.0_wp
        do k = 1, 4
          if (wk%nw(k, c) /= 0.0_wp) vc = vc + wk%nw(k, c)*vel(:, wk%node(k, c))
        end do
        vrel = vc - vwall
        target = -max(gap(c), 0.0_wp)/dt
        ln = max(wk%lam(1, c) + (target - dot_product(vrel, normal))/wk%s(c), 0.0_wp)
        dln = ln - wk%lam(1, c)
        dlt = 0.0_wp
        if (law == CONTACT_STICK .or. law == CONTACT_COULOMB) then
          lt = wk%lam(2, c) - dot_product(vrel, tang)/wk%s(c)
          if (law == CONTACT_COULOMB) lt = max(-friction*ln, min(friction*ln, lt))
          if (ln == 0.0_wp) lt = 0.0_wp          ! no normal push, no friction
          dlt = lt - wk%lam(2, c)
        end if
        if (dln == 0.0_wp .and. dlt == 0.0_wp) cycle
        wk%lam(1, c) = wk%lam(1, c) + dln
        wk%lam(2, c) = wk%lam(2, c) + dlt
        d = dln*normal + dlt*tang
        do k = 1, 4
          if (wk%wt(k, c) == 0.0_wp) cycle
          n = wk%node(k, c)
          vel(:, n) = vel(:, n) + wk%wt(k, c)*d
          if (add_dvel) dvel(:, n) = dvel(:, n) + wk%wt(k, c)*d
        end do
        change = max(change, sqrt(dot_product(d, d))*wk%s(c))
      end do
      wk%sweeps = sweep
      if (change <= sweep_tol*vscale) exit
    end do
    ! the momentum given to the nodes: lambda_c times the sum of its active weights
    do c = 1, npt
      if (.not. wk%s(c) > 0.0_wp) cycle
      impulse = impulse + (wk%lam(1, c)*normal + wk%lam(2, c)*tang)*sum(wk%nw(:, c))
    end do
  end subroutine surface_constrain

  !> Make room for n points.
  subroutine grow(wk, n)
    type(surface_work_t), intent(inout) :: wk  !! work arrays
    integer, intent(in) :: n               !! points
    integer :: m
    if (allocated(wk%s)) then
      if (size(wk%s) >= n) return
      deallocate(wk%node, wk%wt, wk%nw, wk%s, wk%lam)
    end if
    m = max(n, 64)
    allocate(wk%node(4, m), wk%wt(4, m), wk%nw(4, m), wk%s(m), wk%lam(2, m))
  end subroutine grow

end module mpm_surface_contact
