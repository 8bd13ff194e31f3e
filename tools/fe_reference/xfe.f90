! SPDX-License-Identifier: MIT
! xfe: a small explicit dynamic finite element code, the project's own dynamic reference for
! tubempm's impact and wave scenes (docs/fe_reference/README.md, "Dynamic references").
!
! Plane strain, updated Lagrangian 4-node quadrilaterals with 2x2 Gauss points and the mean
! dilatation (B-bar) pressure: the deviatoric part of the rate of deformation at each Gauss
! point, its trace replaced by the element's volume average. Hypoelastic J2 plasticity with
! linear isotropic hardening and the radial return, the stress rotated exactly by the spin
! of the step first (Jaumann), as tubempm's `j2` (docs/method.md). Lumped (row-sum) mass,
! central differences with a time step from the current element sizes. Symmetry planes
! x = 0 (and y = centre for a quarter ring); a rigid frictionless wall y = y_w(t) below the
! body as a node-on-plane kinematic constraint (optionally tied: a node that touched it
! follows it), with a prescribed piecewise-linear velocity table.
!
!   xfe CASE.nml          run the case (&fe namelist, below), write its history CSV
!   xfe --selftest        unit checks; prints `xfe_selftest: N passed, M failed`
module xfe_kinds
  implicit none
  private
  integer, parameter, public :: wp = selected_real_kind(15, 300)
  real(wp), parameter, public :: pi = 3.14159265358979323846_wp
end module xfe_kinds

!> Material: hypoelastic J2 (Jaumann rotation, elastic trial, radial return), stored energy.
module xfe_material
  use xfe_kinds, only: wp
  implicit none
  private
  public :: material_t, material_init, rotate_stress, j2_update, stored_energy

  type :: material_t
    real(wp) :: E = 0.0_wp, nu = 0.0_wp, rho = 0.0_wp
    real(wp) :: sigma_y = 0.0_wp     !< <= 0: elastic
    real(wp) :: hardening = 0.0_wp
    real(wp) :: lambda = 0.0_wp, mu = 0.0_wp, bulk = 0.0_wp, c_d = 0.0_wp
  end type material_t

contains

  pure function material_init(E, nu, rho, sigma_y, hardening) result(m)
    real(wp), intent(in) :: E, nu, rho, sigma_y, hardening
    type(material_t) :: m
    m%E = E; m%nu = nu; m%rho = rho; m%sigma_y = sigma_y; m%hardening = hardening
    m%lambda = E * nu / ((1.0_wp + nu) * (1.0_wp - 2.0_wp * nu))
    m%mu = E / (2.0_wp * (1.0_wp + nu))
    m%bulk = E / (3.0_wp * (1.0_wp - 2.0_wp * nu))
    m%c_d = sqrt((m%lambda + 2.0_wp * m%mu) / rho)
  end function material_init

  !> sigma = (xx, yy, xy, zz) <- Q sigma Q^T, Q the rotation by the angle theta.
  pure subroutine rotate_stress(sig, theta)
    real(wp), intent(inout) :: sig(4)
    real(wp), intent(in) :: theta
    real(wp) :: c, s, sxx, syy, sxy
    c = cos(theta); s = sin(theta)
    sxx = sig(1); syy = sig(2); sxy = sig(3)
    sig(1) = c * c * sxx - 2.0_wp * c * s * sxy + s * s * syy
    sig(2) = s * s * sxx + 2.0_wp * c * s * sxy + c * c * syy
    sig(3) = c * s * (sxx - syy) + (c * c - s * s) * sxy
  end subroutine rotate_stress

  !> Elastic trial from the strain increment de = (xx, yy, xy, zz) (tensor components), then
  !> the radial return; deqps the plastic increment, k_end the flow stress after it.
  pure subroutine j2_update(m, sig, eqps, de, deqps, k_end)
    type(material_t), intent(in) :: m
    real(wp), intent(inout) :: sig(4), eqps
    real(wp), intent(in) :: de(4)
    real(wp), intent(out) :: deqps, k_end
    real(wp) :: tr, p, s(4), q, k
    tr = de(1) + de(2) + de(4)
    sig(1) = sig(1) + m%lambda * tr + 2.0_wp * m%mu * de(1)
    sig(2) = sig(2) + m%lambda * tr + 2.0_wp * m%mu * de(2)
    sig(3) = sig(3) + 2.0_wp * m%mu * de(3)
    sig(4) = sig(4) + m%lambda * tr + 2.0_wp * m%mu * de(4)
    deqps = 0.0_wp
    k_end = 0.0_wp
    if (m%sigma_y <= 0.0_wp) return
    p = (sig(1) + sig(2) + sig(4)) / 3.0_wp
    s = [sig(1) - p, sig(2) - p, sig(3), sig(4) - p]
    q = sqrt(1.5_wp * (s(1)**2 + s(2)**2 + s(4)**2 + 2.0_wp * s(3)**2))
    k = m%sigma_y + m%hardening * eqps
    k_end = k
    if (q <= k) return
    deqps = (q - k) / (3.0_wp * m%mu + m%hardening)
    s = s * (1.0_wp - 3.0_wp * m%mu * deqps / q)
    eqps = eqps + deqps
    k_end = m%sigma_y + m%hardening * eqps
    sig = [s(1) + p, s(2) + p, s(3), s(4) + p]
  end subroutine j2_update

  !> (1/2) sigma : C^-1 : sigma per unit volume (3-D isotropic compliance).
  pure real(wp) function stored_energy(m, sig) result(w)
    type(material_t), intent(in) :: m
    real(wp), intent(in) :: sig(4)
    real(wp) :: p, ss
    p = (sig(1) + sig(2) + sig(4)) / 3.0_wp
    ss = (sig(1) - p)**2 + (sig(2) - p)**2 + (sig(4) - p)**2 + 2.0_wp * sig(3)**2
    w = ss / (4.0_wp * m%mu) + p * p / (2.0_wp * m%bulk)
  end function stored_energy
end module xfe_material

!> The bilinear quadrilateral: Gauss points, gradients, mean gradients.
module xfe_element
  use xfe_kinds, only: wp
  implicit none
  private
  public :: quad_gradients, quad_shape, inverse_map, char_length

  real(wp), parameter :: xi_a(4) = [-1.0_wp, 1.0_wp, 1.0_wp, -1.0_wp]
  real(wp), parameter :: eta_a(4) = [-1.0_wp, -1.0_wp, 1.0_wp, 1.0_wp]
  real(wp), parameter :: gq = 0.57735026918962576451_wp
  real(wp), parameter, public :: xi_g(4) = [-gq, gq, gq, -gq]
  real(wp), parameter, public :: eta_g(4) = [-gq, -gq, gq, gq]

contains

  !> Shape functions and their local derivatives at (xi, eta).
  pure subroutine quad_shape(xi, eta, n, dn)
    real(wp), intent(in) :: xi, eta
    real(wp), intent(out) :: n(4), dn(2, 4)
    n = 0.25_wp * (1.0_wp + xi_a * xi) * (1.0_wp + eta_a * eta)
    dn(1, :) = 0.25_wp * xi_a * (1.0_wp + eta_a * eta)
    dn(2, :) = 0.25_wp * eta_a * (1.0_wp + xi_a * xi)
  end subroutine quad_shape

  !> Gradients g(:, a, gp) of the shape functions at the 4 Gauss points of the element with
  !> corners xe, and the integration weights wdet(gp) = det J (unit Gauss weights); ok false
  !> when a Jacobian is not positive.
  pure subroutine quad_gradients(xe, g, wdet, ok)
    real(wp), intent(in) :: xe(2, 4)
    real(wp), intent(out) :: g(2, 4, 4), wdet(4)
    logical, intent(out) :: ok
    real(wp) :: n(4), dn(2, 4), jac(2, 2), det
    integer :: ip, a
    ok = .true.
    do ip = 1, 4
      call quad_shape(xi_g(ip), eta_g(ip), n, dn)
      jac = matmul(xe, transpose(dn))          ! jac(i, k) = d x_i / d xi_k
      det = jac(1, 1) * jac(2, 2) - jac(1, 2) * jac(2, 1)
      if (det <= 0.0_wp) ok = .false.
      wdet(ip) = det
      do a = 1, 4
        g(1, a, ip) = (jac(2, 2) * dn(1, a) - jac(2, 1) * dn(2, a)) / det
        g(2, a, ip) = (-jac(1, 2) * dn(1, a) + jac(1, 1) * dn(2, a)) / det
      end do
    end do
  end subroutine quad_gradients

  !> Area over the longest diagonal: the length that sets the stable time step.
  pure real(wp) function char_length(xe) result(l)
    real(wp), intent(in) :: xe(2, 4)
    real(wp) :: area, d1, d2
    area = 0.5_wp * ((xe(1, 3) - xe(1, 1)) * (xe(2, 4) - xe(2, 2)) &
                     - (xe(1, 4) - xe(1, 2)) * (xe(2, 3) - xe(2, 1)))
    d1 = norm2(xe(:, 3) - xe(:, 1))
    d2 = norm2(xe(:, 4) - xe(:, 2))
    l = area / max(d1, d2)
  end function char_length

  !> Local coordinates of the point p in the element xe (Newton); inside when both lie in
  !> [-1 - tol, 1 + tol].
  pure subroutine inverse_map(xe, p, xi, eta, inside)
    real(wp), intent(in) :: xe(2, 4), p(2)
    real(wp), intent(out) :: xi, eta
    logical, intent(out) :: inside
    real(wp) :: n(4), dn(2, 4), jac(2, 2), det, r(2)
    integer :: it
    xi = 0.0_wp; eta = 0.0_wp
    do it = 1, 30
      call quad_shape(xi, eta, n, dn)
      r = matmul(xe, n) - p
      jac = matmul(xe, transpose(dn))
      det = jac(1, 1) * jac(2, 2) - jac(1, 2) * jac(2, 1)
      if (det <= 0.0_wp) exit
      xi = xi - (jac(2, 2) * r(1) - jac(1, 2) * r(2)) / det
      eta = eta - (-jac(2, 1) * r(1) + jac(1, 1) * r(2)) / det
      if (abs(xi) > 10.0_wp .or. abs(eta) > 10.0_wp) exit
    end do
    inside = abs(xi) <= 1.0_wp + 1.0e-9_wp .and. abs(eta) <= 1.0_wp + 1.0e-9_wp
  end subroutine inverse_map
end module xfe_element

!> The mesh and the model: nodes, elements, constraints, state.
module xfe_model
  use xfe_kinds, only: wp, pi
  use xfe_material, only: material_t
  implicit none
  private
  public :: model_t, build_ring, build_rect, lump_mass

  type :: model_t
    integer :: nn = 0, ne = 0
    real(wp), allocatable :: x0(:, :), x(:, :), v(:, :), mass(:)
    integer, allocatable :: conn(:, :)
    logical, allocatable :: fix_x(:), fix_y(:), touched(:)
    real(wp), allocatable :: sig(:, :, :), eqps(:, :)   ! (4, gp, element), (gp, element)
    real(wp), allocatable :: force(:, :)                ! internal force (2, node)
    type(material_t) :: mat
    real(wp) :: mult_x = 1.0_wp, mult_y = 1.0_wp        ! mirror multiplicities
  end type model_t

contains

  subroutine allocate_model(md, nn, ne)
    type(model_t), intent(inout) :: md
    integer, intent(in) :: nn, ne
    md%nn = nn; md%ne = ne
    allocate(md%x0(2, nn), md%x(2, nn), md%v(2, nn), md%mass(nn), md%force(2, nn))
    allocate(md%conn(4, ne), md%fix_x(nn), md%fix_y(nn), md%touched(nn))
    allocate(md%sig(4, 4, ne), md%eqps(4, ne))
    md%fix_x = .false.; md%fix_y = .false.; md%touched = .false.
    md%sig = 0.0_wp; md%eqps = 0.0_wp; md%v = 0.0_wp; md%force = 0.0_wp
  end subroutine allocate_model

  !> A ring sector: n_t elements through the wall, n_c around; sector 'half' (x >= 0,
  !> mirror x = 0) or 'quarter' (x >= 0, y <= y_c; mirrors x = 0 and y = y_c).
  subroutine build_ring(md, r_in, r_out, centre, n_t, n_c, sector)
    type(model_t), intent(inout) :: md
    real(wp), intent(in) :: r_in, r_out, centre(2)
    integer, intent(in) :: n_t, n_c
    character(len=*), intent(in) :: sector
    real(wp) :: span, r, phi
    integer :: j, k, id, e
    span = merge(0.5_wp * pi, pi, sector == 'quarter')
    call allocate_model(md, (n_t + 1) * (n_c + 1), n_t * n_c)
    do k = 0, n_c
      phi = -0.5_wp * pi + span * real(k, wp) / real(n_c, wp)
      do j = 0, n_t
        id = node_id(j, k)
        r = r_in + (r_out - r_in) * real(j, wp) / real(n_t, wp)
        md%x0(:, id) = centre + r * [cos(phi), sin(phi)]
        if (k == 0) md%x0(1, id) = centre(1)
        if (k == n_c .and. sector /= 'quarter') md%x0(1, id) = centre(1)
        if (k == n_c .and. sector == 'quarter') md%x0(2, id) = centre(2)
        md%fix_x(id) = k == 0 .or. (k == n_c .and. sector /= 'quarter')
        md%fix_y(id) = k == n_c .and. sector == 'quarter'
      end do
    end do
    do k = 0, n_c - 1
      do j = 0, n_t - 1
        e = 1 + j + n_t * k
        md%conn(:, e) = [node_id(j, k), node_id(j + 1, k), node_id(j + 1, k + 1), node_id(j, k + 1)]
      end do
    end do
    md%mult_x = 2.0_wp
    md%mult_y = merge(2.0_wp, 1.0_wp, sector == 'quarter')
    md%x = md%x0
  contains
    pure integer function node_id(jj, kk)
      integer, intent(in) :: jj, kk
      node_id = 1 + jj + (n_t + 1) * kk
    end function node_id
  end subroutine build_ring

  !> A rectangle [lower, upper] with nx x ny elements; mirror_x: x = lower(1) is a mirror plane.
  subroutine build_rect(md, lower, upper, nx, ny, mirror_x)
    type(model_t), intent(inout) :: md
    real(wp), intent(in) :: lower(2), upper(2)
    integer, intent(in) :: nx, ny
    logical, intent(in) :: mirror_x
    integer :: i, j, id, e
    call allocate_model(md, (nx + 1) * (ny + 1), nx * ny)
    do j = 0, ny
      do i = 0, nx
        id = 1 + i + (nx + 1) * j
        md%x0(:, id) = lower + (upper - lower) * [real(i, wp) / nx, real(j, wp) / ny]
        md%fix_x(id) = mirror_x .and. i == 0
      end do
    end do
    do j = 0, ny - 1
      do i = 0, nx - 1
        e = 1 + i + nx * j
        id = 1 + i + (nx + 1) * j
        md%conn(:, e) = [id, id + 1, id + nx + 2, id + nx + 1]
      end do
    end do
    md%mult_x = merge(2.0_wp, 1.0_wp, mirror_x)
    md%x = md%x0
  end subroutine build_rect

  !> Row-sum lumped mass rho * integral of N_a over the reference element.
  subroutine lump_mass(md)
    use xfe_element, only: quad_shape, xi_g, eta_g
    type(model_t), intent(inout) :: md
    real(wp) :: n(4), dn(2, 4), jac(2, 2), det
    integer :: e, ip
    md%mass = 0.0_wp
    do e = 1, md%ne
      do ip = 1, 4
        call quad_shape(xi_g(ip), eta_g(ip), n, dn)
        jac = matmul(md%x0(:, md%conn(:, e)), transpose(dn))
        det = jac(1, 1) * jac(2, 2) - jac(1, 2) * jac(2, 1)
        md%mass(md%conn(:, e)) = md%mass(md%conn(:, e)) + md%mat%rho * det * n
      end do
    end do
  end subroutine lump_mass
end module xfe_model

!> Internal forces and the stress update of one step.
module xfe_forces
  use xfe_kinds, only: wp
  use xfe_model, only: model_t
  use xfe_material, only: rotate_stress, j2_update, stored_energy
  use xfe_element, only: quad_gradients, char_length
  implicit none
  private
  public :: update_stress, internal_forces

contains

  !> Advance the Gauss point stresses over dt with the velocity v (the step's v^{n+1/2}) on
  !> the mid-step configuration xmid; returns the plastic work of the step (model part, per
  !> unit depth) and ok = .false. when an element inverts.
  subroutine update_stress(md, xmid, dt, dwp, ok)
    type(model_t), intent(inout) :: md
    real(wp), intent(in) :: xmid(:, :), dt
    real(wp), intent(out) :: dwp
    logical, intent(out) :: ok
    real(wp) :: g(2, 4, 4), wdet(4), ve(2, 4), lg(2, 2, 4), trd(4), trbar, de(4), deqps, k_end
    integer :: e, ip
    logical :: oke
    dwp = 0.0_wp
    ok = .true.
    do e = 1, md%ne
      call quad_gradients(xmid(:, md%conn(:, e)), g, wdet, oke)
      if (.not. oke) ok = .false.
      ve = md%v(:, md%conn(:, e))
      do ip = 1, 4
        lg(:, :, ip) = matmul(ve, transpose(g(:, :, ip)))    ! L_ij = sum_a v_ia dN_a/dx_j
        trd(ip) = lg(1, 1, ip) + lg(2, 2, ip)
      end do
      trbar = sum(trd * wdet) / sum(wdet)
      do ip = 1, 4
        call rotate_stress(md%sig(:, ip, e), 0.5_wp * (lg(2, 1, ip) - lg(1, 2, ip)) * dt)
        de(1) = lg(1, 1, ip) + (trbar - trd(ip)) / 3.0_wp
        de(2) = lg(2, 2, ip) + (trbar - trd(ip)) / 3.0_wp
        de(3) = 0.5_wp * (lg(1, 2, ip) + lg(2, 1, ip))
        de(4) = (trbar - trd(ip)) / 3.0_wp
        call j2_update(md%mat, md%sig(:, ip, e), md%eqps(ip, e), de * dt, deqps, k_end)
        dwp = dwp + k_end * deqps * wdet(ip)
      end do
    end do
  end subroutine update_stress

  !> md%force = the internal forces on the current configuration (B-bar: deviatoric stress
  !> with the Gauss point gradients, mean stress with the element's mean gradients); also
  !> the stored elastic energy (model part, per unit depth) and the smallest element length.
  subroutine internal_forces(md, strain, lmin, ok)
    type(model_t), intent(inout) :: md
    real(wp), intent(out) :: strain, lmin
    logical, intent(out) :: ok
    real(wp) :: g(2, 4, 4), wdet(4), gbar(2, 4), fe(2, 4), s(4), p
    integer :: e, ip, a
    logical :: oke
    md%force = 0.0_wp
    strain = 0.0_wp
    lmin = huge(1.0_wp)
    ok = .true.
    do e = 1, md%ne
      call quad_gradients(md%x(:, md%conn(:, e)), g, wdet, oke)
      if (.not. oke) ok = .false.
      gbar = 0.0_wp
      do ip = 1, 4
        gbar = gbar + g(:, :, ip) * wdet(ip)
      end do
      gbar = gbar / sum(wdet)
      fe = 0.0_wp
      do ip = 1, 4
        s = md%sig(:, ip, e)
        p = (s(1) + s(2) + s(4)) / 3.0_wp
        do a = 1, 4
          fe(1, a) = fe(1, a) + wdet(ip) * ((s(1) - p) * g(1, a, ip) + s(3) * g(2, a, ip) &
                                            + p * gbar(1, a))
          fe(2, a) = fe(2, a) + wdet(ip) * (s(3) * g(1, a, ip) + (s(2) - p) * g(2, a, ip) &
                                            + p * gbar(2, a))
        end do
        strain = strain + stored_energy(md%mat, s) * wdet(ip)
      end do
      md%force(:, md%conn(:, e)) = md%force(:, md%conn(:, e)) + fe
      lmin = min(lmin, char_length(md%x(:, md%conn(:, e))))
    end do
  end subroutine internal_forces
end module xfe_forces

!> The rigid wall y = y_w(t): velocity table, position, the node-on-plane constraint.
module xfe_wall
  use xfe_kinds, only: wp
  implicit none
  private
  public :: wall_t, wall_velocity, wall_position

  type :: wall_t
    logical :: on = .false.
    logical :: tied = .false.
    real(wp) :: y0 = 0.0_wp
    real(wp) :: speed = 0.0_wp         !< velocity along +y, scaled by the table
    integer :: n_table = 0
    real(wp) :: tt(32) = 0.0_wp, ff(32) = 0.0_wp
  end type wall_t

contains

  !> The table factor at t (linear between points, the end values held outside).
  pure real(wp) function factor(w, t)
    type(wall_t), intent(in) :: w
    real(wp), intent(in) :: t
    integer :: i
    if (w%n_table == 0) then
      factor = 1.0_wp
      return
    end if
    if (t <= w%tt(1)) then
      factor = w%ff(1)
      return
    end if
    do i = 2, w%n_table
      if (t <= w%tt(i)) then
        factor = w%ff(i - 1) + (w%ff(i) - w%ff(i - 1)) * (t - w%tt(i - 1)) / (w%tt(i) - w%tt(i - 1))
        return
      end if
    end do
    factor = w%ff(w%n_table)
  end function factor

  pure real(wp) function wall_velocity(w, t)
    type(wall_t), intent(in) :: w
    real(wp), intent(in) :: t
    wall_velocity = w%speed * factor(w, t)
  end function wall_velocity

  !> y_w(t): the exact integral of the piecewise-linear velocity (the end values held).
  pure real(wp) function wall_position(w, t) result(y)
    type(wall_t), intent(in) :: w
    real(wp), intent(in) :: t
    real(wp) :: a, b
    integer :: i
    y = w%y0
    if (w%n_table == 0) then
      y = w%y0 + w%speed * t
      return
    end if
    y = y + w%speed * w%ff(1) * max(0.0_wp, min(t, w%tt(1)))
    do i = 2, w%n_table
      a = max(0.0_wp, w%tt(i - 1))
      b = min(t, w%tt(i))
      if (b > a) y = y + 0.5_wp * (b - a) * (wall_velocity(w, a) + wall_velocity(w, b))
    end do
    if (t > w%tt(w%n_table)) y = y + (t - w%tt(w%n_table)) * w%speed * w%ff(w%n_table)
  end function wall_position
end module xfe_wall

!> The time loop and the history file.
module xfe_solver
  use xfe_kinds, only: wp
  use xfe_model, only: model_t
  use xfe_wall, only: wall_t, wall_velocity, wall_position
  use xfe_forces, only: update_stress, internal_forces
  use xfe_element, only: inverse_map, quad_shape
  implicit none
  private
  public :: run_t, probe_t, solve, locate_probes

  type :: probe_t
    real(wp) :: p(2) = 0.0_wp
    integer :: elem = 0
    real(wp) :: n(4) = 0.0_wp
  end type probe_t

  type :: run_t
    real(wp) :: t_end = 0.0_wp, cfl = 0.5_wp, every = 1.0e-6_wp
    character(len=512) :: output = 'history.csv'
    real(wp) :: depth = 1.0_wp
  end type run_t

  type :: totals_t
    real(wp) :: kinetic = 0.0_wp, strain = 0.0_wp, plastic = 0.0_wp, external = 0.0_wp
    real(wp) :: com(2) = 0.0_wp, vcom(2) = 0.0_wp, e0 = 0.0_wp, err = 0.0_wp
  end type totals_t

contains

  !> Each probe's element and shape function values at its reference point.
  subroutine locate_probes(md, probes)
    type(model_t), intent(in) :: md
    type(probe_t), intent(inout) :: probes(:)
    real(wp) :: xi, eta, dn(2, 4), best, d
    integer :: k, e
    logical :: inside
    do k = 1, size(probes)
      probes(k)%elem = 0
      best = huge(1.0_wp)
      do e = 1, md%ne
        call inverse_map(md%x0(:, md%conn(:, e)), probes(k)%p, xi, eta, inside)
        d = max(abs(xi), abs(eta))
        if (d < best) then
          best = d
          probes(k)%elem = e
          call quad_shape(max(-1.0_wp, min(1.0_wp, xi)), max(-1.0_wp, min(1.0_wp, eta)), &
                          probes(k)%n, dn)
        end if
      end do
    end do
  end subroutine locate_probes

  subroutine write_header(u, nprobe)
    integer, intent(in) :: u, nprobe
    integer :: k
    write(u, '(a)', advance='no') 'time,wall1_disp,wall1_force,kinetic,strain,plastic,external,' // &
      'com_x,com_y,com_vx,com_vy'
    do k = 1, nprobe
      write(u, '(4(a,i0,a))', advance='no') ',probe', k, '_x', ',probe', k, '_y', &
        ',probe', k, '_vx', ',probe', k, '_vy'
    end do
    write(u, '(a)') ',step,dt,energy_error'
  end subroutine write_header

  subroutine write_row(u, md, probes, t, wdisp, wforce, tot, vnow, step, dt, depth)
    integer, intent(in) :: u, step
    type(model_t), intent(in) :: md
    type(probe_t), intent(in) :: probes(:)
    real(wp), intent(in) :: t, wdisp, wforce, vnow(:, :), dt, depth
    type(totals_t), intent(in) :: tot
    real(wp) :: px(2), pv(2)
    integer :: k
    write(u, '(es23.15e3,10(",",es23.15e3))', advance='no') t, wdisp, wforce * depth, &
      tot%kinetic * depth, tot%strain * depth, tot%plastic * depth, tot%external * depth, &
      tot%com, tot%vcom
    do k = 1, size(probes)
      px = matmul(md%x(:, md%conn(:, probes(k)%elem)), probes(k)%n)
      pv = matmul(vnow(:, md%conn(:, probes(k)%elem)), probes(k)%n)
      write(u, '(4(",",es23.15e3))', advance='no') px, pv
    end do
    write(u, '(",",i0,2(",",es23.15e3))') step, dt, tot%err
  end subroutine write_row

  !> Kinetic energy, centre of mass and its velocity of the full structure (mirrors included).
  subroutine body_totals(md, vnow, tot)
    type(model_t), intent(in) :: md
    real(wp), intent(in) :: vnow(:, :)
    type(totals_t), intent(inout) :: tot
    real(wp) :: mtot, mult
    integer :: i
    mult = md%mult_x * md%mult_y
    mtot = sum(md%mass)
    tot%kinetic = 0.0_wp
    do i = 1, md%nn
      tot%kinetic = tot%kinetic + 0.5_wp * md%mass(i) * sum(vnow(:, i)**2)
    end do
    tot%kinetic = mult * tot%kinetic
    tot%com = matmul(md%x, md%mass) / mtot
    tot%vcom = matmul(vnow, md%mass) / mtot
    if (md%mult_x > 1.0_wp) then
      tot%com(1) = md%x0(1, 1); tot%vcom(1) = 0.0_wp
    end if
    if (md%mult_y > 1.0_wp) tot%vcom(2) = 0.0_wp
  end subroutine body_totals

  !> Symmetry planes and the wall on the step velocity v^{n+1/2}; returns the wall's impulse
  !> on the model part (y, per unit depth: the momentum added to the nodes).
  subroutine constrain(md, w, t_next, dt, impulse)
    type(model_t), intent(inout) :: md
    type(wall_t), intent(in) :: w
    real(wp), intent(in) :: t_next, dt
    real(wp), intent(out) :: impulse
    real(wp) :: yw, vy
    integer :: i
    impulse = 0.0_wp
    where (md%fix_x) md%v(1, :) = 0.0_wp
    where (md%fix_y) md%v(2, :) = 0.0_wp
    if (.not. w%on) return
    yw = wall_position(w, t_next)
    do i = 1, md%nn
      if (md%x(2, i) + dt * md%v(2, i) < yw .or. (w%tied .and. md%touched(i))) then
        vy = (yw - md%x(2, i)) / dt
        impulse = impulse + md%mass(i) * (vy - md%v(2, i))
        md%v(2, i) = vy
        md%touched(i) = .true.
      end if
    end do
  end subroutine constrain

  !> Run to t_end; history rows every run%every (and the first and last step).
  subroutine solve(md, w, run, probes, status)
    type(model_t), intent(inout) :: md
    type(wall_t), intent(in) :: w
    type(run_t), intent(in) :: run
    type(probe_t), intent(in) :: probes(:)
    integer, intent(out) :: status
    real(wp), allocatable :: acc(:, :), vnow(:, :), xold(:, :)
    real(wp) :: t, dt, dt_prev, lmin, strain, dwp, impulse, row_impulse, t_row, t_next_row
    real(wp) :: mult
    type(totals_t) :: tot
    integer :: u, step, ios
    logical :: ok
    allocate(acc(2, md%nn), vnow(2, md%nn), xold(2, md%nn))
    mult = md%mult_x * md%mult_y
    open(newunit=u, file=trim(run%output), status='replace', action='write', iostat=ios)
    if (ios /= 0) then
      write(*, '(a)') 'ERROR [xfe]: cannot write ' // trim(run%output)
      status = 2
      return
    end if
    call write_header(u, size(probes))
    call internal_forces(md, strain, lmin, ok)
    t = 0.0_wp; step = 0; dt_prev = 0.0_wp
    dt = run%cfl * lmin / md%mat%c_d
    row_impulse = 0.0_wp; t_row = 0.0_wp; t_next_row = 0.0_wp
    status = 0
    do
      acc(1, :) = -md%force(1, :) / md%mass
      acc(2, :) = -md%force(2, :) / md%mass
      tot%strain = mult * strain
      vnow = md%v + 0.5_wp * dt_prev * acc
      where (md%fix_x) vnow(1, :) = 0.0_wp
      where (md%fix_y) vnow(2, :) = 0.0_wp
      if (t >= t_next_row - 1.0e-6_wp * dt .or. t >= run%t_end - 1.0e-6_wp * dt) then
        call body_totals(md, vnow, tot)
        if (step == 0) tot%e0 = tot%kinetic + tot%strain
        tot%err = (tot%kinetic + tot%strain + tot%plastic - tot%external - tot%e0) &
                  / max(tot%e0, abs(tot%external), tiny(1.0_wp))
        call write_row(u, md, probes, t, -(wall_position(w, t) - w%y0), &
                       merge(0.0_wp, md%mult_x * row_impulse / max(t - t_row, tiny(1.0_wp)), &
                             step == 0), tot, vnow, step, dt, run%depth)
        row_impulse = 0.0_wp; t_row = t
        t_next_row = t_next_row + run%every
        do while (t_next_row <= t)
          t_next_row = t_next_row + run%every
        end do
      end if
      if (t >= run%t_end - 1.0e-6_wp * dt) exit
      md%v = md%v + 0.5_wp * (dt_prev + dt) * acc
      call constrain(md, w, t + dt, dt, impulse)
      ! the wall's work on the material: impulse times the wall's velocity over the step
      tot%external = tot%external + mult * impulse &
                     * wall_velocity(w, t + 0.5_wp * dt) * merge(1.0_wp, 0.0_wp, w%on)
      row_impulse = row_impulse + impulse
      xold = md%x
      md%x = md%x + dt * md%v
      call update_stress(md, 0.5_wp * (xold + md%x), dt, dwp, ok)
      tot%plastic = tot%plastic + mult * dwp
      call internal_forces(md, strain, lmin, ok)
      if (.not. ok) then
        write(*, '(a,es12.4)') 'ERROR [xfe]: an element inverted at t = ', t + dt
        status = 4
        exit
      end if
      t = t + dt; step = step + 1
      dt_prev = dt
      dt = run%cfl * lmin / md%mat%c_d
      if (t + dt > run%t_end .and. t < run%t_end) dt = max(run%t_end - t, 1.0e-3_wp * dt)
    end do
    close(u)
    write(*, '(a,i0,a,es12.4,a,es12.4)') 'xfe: ', step, ' steps to t = ', t, &
      ', energy error ', tot%err
  end subroutine solve
end module xfe_solver

!> Unit checks of the kernel (xfe --selftest).
module xfe_selftest
  use xfe_kinds, only: wp, pi
  use xfe_model, only: model_t, build_ring, build_rect, lump_mass
  use xfe_material, only: material_init, j2_update, rotate_stress
  use xfe_element, only: quad_gradients
  use xfe_forces, only: update_stress, internal_forces
  use xfe_wall, only: wall_t, wall_position
  implicit none
  private
  public :: run_selftest

  integer :: n_pass = 0, n_fail = 0

contains

  subroutine check(ok, what)
    logical, intent(in) :: ok
    character(len=*), intent(in) :: what
    if (ok) then
      n_pass = n_pass + 1
    else
      n_fail = n_fail + 1
      write(*, '(a)') 'FAIL: ' // what
    end if
  end subroutine check

  !> A distorted quadrilateral reproduces a linear velocity field's gradient exactly.
  subroutine test_gradient_patch()
    real(wp) :: xe(2, 4), ve(2, 4), g(2, 4, 4), wdet(4), a(2, 2), l(2, 2), err
    integer :: ip
    logical :: ok
    xe = reshape([0.0_wp, 0.0_wp, 1.3_wp, 0.2_wp, 1.1_wp, 0.9_wp, -0.2_wp, 1.4_wp], [2, 4])
    a = reshape([0.3_wp, -1.7_wp, 2.1_wp, 0.45_wp], [2, 2])
    ve = matmul(a, xe) + spread([0.7_wp, -0.1_wp], 2, 4)
    call quad_gradients(xe, g, wdet, ok)
    err = 0.0_wp
    do ip = 1, 4
      l = matmul(ve, transpose(g(:, :, ip)))
      err = max(err, maxval(abs(l - a)))
    end do
    call check(ok .and. err < 1.0e-12_wp, 'gradient patch test')
    call check(abs(sum(wdet) - shoelace(xe)) < 1.0e-12_wp, 'Gauss weights sum to the area')
  end subroutine test_gradient_patch

  pure real(wp) function shoelace(xe)
    real(wp), intent(in) :: xe(2, 4)
    shoelace = 0.5_wp * ((xe(1, 3) - xe(1, 1)) * (xe(2, 4) - xe(2, 2)) &
                         - (xe(1, 4) - xe(1, 2)) * (xe(2, 3) - xe(2, 1)))
  end function shoelace

  !> A uniform stress on the curved ring mesh leaves every interior node without force.
  subroutine test_force_patch()
    type(model_t) :: md
    real(wp) :: strain, lmin, fmax, fint
    integer :: j, k, id
    logical :: ok
    md%mat = material_init(70.0e9_wp, 0.33_wp, 2700.0_wp, 0.0_wp, 0.0_wp)
    call build_ring(md, 24.0e-3_wp, 26.0e-3_wp, [0.0_wp, 0.026_wp], 3, 17, 'half')
    do k = 1, md%ne
      md%sig(:, :, k) = spread([1.0e8_wp, -3.0e7_wp, 4.0e7_wp, 2.0e7_wp], 2, 4)
    end do
    call internal_forces(md, strain, lmin, ok)
    fmax = maxval(abs(md%force))
    fint = 0.0_wp
    do k = 1, 16
      do j = 1, 2
        id = 1 + j + 4 * k
        fint = max(fint, maxval(abs(md%force(:, id))))
      end do
    end do
    call check(ok .and. fint < 1.0e-10_wp * fmax, 'force patch test (uniform stress)')
  end subroutine test_force_patch

  !> A rigid spin rotates the stress and strains nothing: a quarter turn swaps xx and yy.
  subroutine test_rigid_rotation()
    type(model_t) :: md
    real(wp) :: omega, dt, dwp, s0(4), err
    integer :: n, i
    logical :: ok, ok_all
    md%mat = material_init(70.0e9_wp, 0.33_wp, 2700.0_wp, 150.0e6_wp, 200.0e6_wp)
    call build_rect(md, [1.0e-3_wp, 2.0e-3_wp], [2.0e-3_wp, 4.0e-3_wp], 1, 1, .false.)
    s0 = [1.0e8_wp, -2.0e7_wp, 3.0e7_wp, 1.0e7_wp]
    md%sig(:, :, 1) = spread(s0, 2, 4)
    omega = 1.0e3_wp
    n = 2000
    dt = 0.5_wp * pi / omega / n
    ok_all = .true.
    do i = 1, n
      ! the exact rigid rotation by omega dt over the step, v = its chord over dt: the mid-step
      ! configuration then sees a pure spin (the Cayley transform)
      md%x0 = md%x
      md%x(1, :) = cos(omega * dt) * md%x0(1, :) - sin(omega * dt) * md%x0(2, :)
      md%x(2, :) = sin(omega * dt) * md%x0(1, :) + cos(omega * dt) * md%x0(2, :)
      md%v = (md%x - md%x0) / dt
      call update_stress(md, 0.5_wp * (md%x0 + md%x), dt, dwp, ok)
      ok_all = ok_all .and. ok
    end do
    err = maxval(abs(md%sig(:, 1, 1) - [s0(2), s0(1), -s0(3), s0(4)])) / maxval(abs(s0))
    call check(ok_all .and. err < 1.0e-6_wp, 'rigid rotation: a quarter turn of the stress')
  end subroutine test_rigid_rotation

  !> Uniaxial straining in plane strain: elastic slope lambda + 2 mu, then the stress on the
  !> hardened surface q = sigma_y + H eqps, the plastic work positive.
  subroutine test_return()
    real(wp) :: sig(4), eqps, deqps, k_end, q, p, err_c, d
    integer :: i
    type(model_t) :: md
    md%mat = material_init(70.0e9_wp, 0.33_wp, 2700.0_wp, 150.0e6_wp, 200.0e6_wp)
    sig = 0.0_wp; eqps = 0.0_wp
    d = 1.0e-5_wp
    call j2_update(md%mat, sig, eqps, [d, 0.0_wp, 0.0_wp, 0.0_wp], deqps, k_end)
    call check(abs(sig(1) - (md%mat%lambda + 2.0_wp * md%mat%mu) * d) < 1.0e-9_wp * abs(sig(1)) &
               .and. deqps <= 0.0_wp, 'elastic step: sigma_xx = (lambda + 2 mu) de')
    err_c = 0.0_wp
    do i = 1, 2000
      call j2_update(md%mat, sig, eqps, [d, 0.0_wp, 0.0_wp, 0.0_wp], deqps, k_end)
      if (deqps > 0.0_wp) then
        p = (sig(1) + sig(2) + sig(4)) / 3.0_wp
        q = sqrt(1.5_wp * ((sig(1) - p)**2 + (sig(2) - p)**2 + (sig(4) - p)**2 + 2.0_wp * sig(3)**2))
        err_c = max(err_c, abs(q - (150.0e6_wp + 200.0e6_wp * eqps)) / q)
      end if
    end do
    call check(eqps > 0.0_wp .and. err_c < 1.0e-12_wp, 'radial return: q = sigma_y + H eqps')
    ! uniaxial strain: the plastic eqps rate tends to 2 d (3 mu) / (3 (3 mu + H)) ... only its
    ! sign and the stress ordering are checked here
    call check(sig(1) > sig(4) .and. sig(4) >= sig(2) - 1.0_wp, 'stress ordering xx > zz = yy')
  end subroutine test_return

  !> The wall table: the wave's 10 m/s pulse moves the wall 10 um by 2 us and 100 um by 12 us.
  subroutine test_wall_table()
    type(wall_t) :: w
    w%on = .true.; w%speed = 10.0_wp; w%n_table = 4
    w%tt(1:4) = [0.0_wp, 2.0e-6_wp, 1.0e-5_wp, 1.2e-5_wp]
    w%ff(1:4) = [0.0_wp, 1.0_wp, 1.0_wp, 0.0_wp]
    call check(abs(wall_position(w, 2.0e-6_wp) - 1.0e-5_wp) < 1.0e-15_wp, 'wall position at 2 us')
    call check(abs(wall_position(w, 1.2e-5_wp) - 1.0e-4_wp) < 1.0e-15_wp, 'wall position at 12 us')
    call check(abs(wall_position(w, 5.0e-5_wp) - 1.0e-4_wp) < 1.0e-15_wp, 'wall held after 12 us')
    call check(abs(wall_position(w, 1.0e-6_wp) - 2.5e-6_wp) < 1.0e-15_wp, 'wall position at 1 us')
  end subroutine test_wall_table

  !> The lumped masses add up to rho times the mesh's area.
  subroutine test_mass()
    type(model_t) :: md
    md%mat = material_init(70.0e9_wp, 0.33_wp, 2700.0_wp, 0.0_wp, 0.0_wp)
    call build_rect(md, [0.0_wp, 0.0_wp], [2.0e-3_wp, 5.0e-3_wp], 3, 7, .true.)
    call lump_mass(md)
    call check(abs(sum(md%mass) - 2700.0_wp * 1.0e-5_wp) < 1.0e-12_wp * 2700.0_wp * 1.0e-5_wp, &
               'lumped mass = rho A')
  end subroutine test_mass

  integer function run_selftest() result(n_failed)
    call test_gradient_patch()
    call test_force_patch()
    call test_rigid_rotation()
    call test_return()
    call test_wall_table()
    call test_mass()
    write(*, '(a,i0,a,i0,a)') 'xfe_selftest: ', n_pass, ' passed, ', n_fail, ' failed'
    n_failed = n_fail
  end function run_selftest
end module xfe_selftest

program xfe
  use xfe_kinds, only: wp, pi
  use xfe_model, only: model_t, build_ring, build_rect, lump_mass
  use xfe_material, only: material_init
  use xfe_wall, only: wall_t
  use xfe_solver, only: run_t, probe_t, solve, locate_probes
  use xfe_selftest, only: run_selftest
  implicit none
  integer, parameter :: max_table = 32, max_probe = 16
  character(len=16) :: shape, sector
  character(len=512) :: output, arg
  real(wp) :: r_inner, r_outer, center(2), lower(2), upper(2), velocity(2)
  real(wp) :: E, nu, rho, sigma_y, hardening
  real(wp) :: wall_y, wall_speed, motion_t(max_table), motion_f(max_table)
  real(wp) :: t_end, cfl, history_every, depth, probe_x(max_probe), probe_y(max_probe)
  integer :: n_t, n_c, nx, ny, u, ios, n_probe, k, status
  logical :: wall, wall_tied, mirror_x, rollers
  namelist /fe/ shape, sector, r_inner, r_outer, center, lower, upper, n_t, n_c, nx, ny, &
    mirror_x, rollers, velocity, E, nu, rho, sigma_y, hardening, wall, wall_tied, wall_y, &
    wall_speed, motion_t, motion_f, t_end, cfl, history_every, depth, output, probe_x, probe_y
  type(model_t) :: md
  type(wall_t) :: w
  type(run_t) :: run
  type(probe_t), allocatable :: probes(:)

  if (command_argument_count() /= 1) then
    write(*, '(a)') 'usage: xfe CASE.nml | xfe --selftest'
    stop 2
  end if
  call get_command_argument(1, arg)
  if (trim(arg) == '--selftest') then
    if (run_selftest() /= 0) stop 1
    stop
  end if

  shape = 'ring'; sector = 'half'; r_inner = 24.0e-3_wp; r_outer = 26.0e-3_wp
  center = [0.0_wp, 0.0265_wp]; lower = 0.0_wp; upper = 0.0_wp
  n_t = 4; n_c = 0; nx = 1; ny = 1; mirror_x = .false.; rollers = .false.
  velocity = 0.0_wp; E = 70.0e9_wp; nu = 0.33_wp; rho = 2700.0_wp
  sigma_y = 150.0e6_wp; hardening = 200.0e6_wp
  wall = .true.; wall_tied = .false.; wall_y = 0.0_wp; wall_speed = 0.0_wp
  motion_t = -1.0_wp; motion_f = 0.0_wp
  t_end = 1.0e-4_wp; cfl = 0.5_wp; history_every = 1.0e-6_wp; depth = 1.0_wp
  output = 'history.csv'; probe_x = huge(1.0_wp); probe_y = huge(1.0_wp)
  open(newunit=u, file=trim(arg), status='old', action='read', iostat=ios)
  if (ios == 0) read(u, nml=fe, iostat=ios)
  if (ios /= 0) then
    write(*, '(a)') 'ERROR [xfe]: cannot read the &fe namelist of ' // trim(arg)
    stop 2
  end if
  close(u)

  md%mat = material_init(E, nu, rho, sigma_y, hardening)
  if (shape == 'ring') then
    if (n_c <= 0) n_c = max(1, nint(merge(0.5_wp, 1.0_wp, sector == 'quarter') * pi &
                                     * 0.5_wp * (r_inner + r_outer) / ((r_outer - r_inner) / n_t)))
    call build_ring(md, r_inner, r_outer, center, n_t, n_c, sector)
  else
    call build_rect(md, lower, upper, nx, ny, mirror_x)
  end if
  if (rollers) md%fix_x = .true.
  call lump_mass(md)
  md%v(1, :) = velocity(1); md%v(2, :) = velocity(2)
  where (md%fix_x) md%v(1, :) = 0.0_wp

  w%on = wall; w%tied = wall_tied; w%y0 = wall_y; w%speed = wall_speed
  w%n_table = count(motion_t >= 0.0_wp)
  w%tt(1:w%n_table) = motion_t(1:w%n_table)
  w%ff(1:w%n_table) = motion_f(1:w%n_table)

  n_probe = count(probe_x < huge(1.0_wp))
  allocate(probes(n_probe))
  do k = 1, n_probe
    probes(k)%p = [probe_x(k), probe_y(k)]
  end do
  call locate_probes(md, probes)

  run%t_end = t_end; run%cfl = cfl; run%every = history_every; run%depth = depth
  run%output = output
  write(*, '(a,i0,a,i0,a,i0)') 'xfe: ', md%ne, ' elements, ', md%nn, ' nodes; n_c = ', n_c
  call solve(md, w, run, probes, status)
  if (status /= 0) stop 1
end program xfe
