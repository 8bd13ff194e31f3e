!> Contact between bodies (multi-field MPM): each body has its own velocity field on the grid;
!! where two fields share a node their surfaces are found from the particle domains, and the
!! contact law (mpm_contact_law) exchanges momentum between them when the surfaces meet.
! SPDX-License-Identifier: MIT
!
! Called by the step (mpm_solver) only where the case has more than one velocity field
! (params_t%nf > 1); a case with one body never comes here and is computed as before.
!   detect (after P2G of the masses): the contact nodes, where two fields or more have mass;
!     at each the local centre of mass of every field, x_f = sum_p phi_ip m_p x_p / m_f over
!     the particles of f; for each pair of fields (a, b) the direction between them (from a
!     into b; on a mirror plane its component across the plane is dropped); the domain corners
!     of a's and b's particles that touch the node, within a cell of it along the surface
!     (CPDI2: the shared corners; CPDI1: x -+ F r10 -+ F r20; uGIMP and linear: x -+ F
!     (half_x, 0) -+ F (0, half_y), the particle's square deformed with it); the normal n, the
!     direction within 60 degrees of that one that separates b's corners from a's the most
!     (turning either way alike, and only where the turn gains more than 1e-6 h: mirror-image
!     bodies get mirror-image normals), and the gap, that separation (the smallest x . n over
!     b's corners minus the largest over a's). The surfaces are exact where the domains are
!     (CPDI), so contact engages when they meet, not when the fields first share a node (a
!     cell or more early); two surfaces that touch get the normal of their common tangent
!     (the centre-of-mass direction tilts near the contact point of a curved surface, and a
!     body sliding on it ploughed).
!     Why not the mass gradients (Bardenhagen et al. 2001) for n: where a wall is two cells
!     thick both of its faces fall in a node's support and their contributions nearly cancel;
!     on two rings t = 2h the gradient normal pointed the wrong way at half the contact nodes
!     and the rings did not part. Why the corner window: without it the corners of a curved
!     surface a cell or more aside of the node set the extremes, contact engages early, and
!     two rings rebounded 5 % slower than one ring from a wall (2 % with it).
!   apply (after the velocity update of step 3, and on the velocities of the MUSL re-map): at
!     every pair entry, the impulse of the law (mpm_contact_law); in step 3 it also enters the
!     velocity change that FLIP adds to the particles, and the pair's impulse for history.csv.
!     The re-map needs it too: its velocities move the domains and deform the particles, and
!     without the contact there the blocks of a pressed stack gained energy until exit 4 (at
!     cfl 0.3 and above); it acts there without friction (see body_contact_apply).
module mpm_body_contact
  use mpm_kinds, only: wp
  use mpm_constants, only: CONTACT_SLIP, CONTACT_FRICTIONLESS, CONTACT_BONDED, BASIS_CPDI2, &
                           SCHEME_USL
  use mpm_particles, only: particles_t, particle_corners
  use mpm_grid, only: grid_t
  use mpm_tiles, only: tiles_t, tiles_span
  use mpm_contact_law, only: field_contact_t, contact_law_impulse, field_contact_reserve
  use mpm_state, only: params_t, state_t, work_t
  use mpm_body_tie, only: body_tie_nodes
  implicit none
  private
  public :: body_contact_detect, body_contact_apply, body_contact_reactions, pair_index, &
            body_contact_loss

  real(wp), parameter :: no_gap = 1.0e30_wp  !! gap of an entry whose surfaces were not found [m]
  real(wp), parameter :: tang_window = 1.0_wp  !! corners count within this many cells of the
                                               !! node along the surface [-]
  real(wp), parameter :: sep_eps = 1.0e-6_wp   !! separations closer than this many cells are
                                               !! equal (separating_normal) [-]
  integer, parameter :: n_marks = 8            !! entries a corner remembers being gathered for
                                               !! (a repeat beyond them is harmless) [-]

contains

  !> Index of the pair of bodies i /= j among the pairs (1, 2), (1, 3), ..., (1, n), (2, 3),
  !! ... of n bodies.
  pure integer function pair_index(i, j, n) result(k)
    integer, intent(in) :: i, j            !! the two bodies
    integer, intent(in) :: n               !! bodies
    integer :: a, b
    a = min(i, j)
    b = max(i, j)
    k = (a - 1)*n - (a*(a - 1))/2 + (b - a)
  end function pair_index

  !> Contact nodes, normals and gaps of the step (after P2G of the masses).
  subroutine body_contact_detect(prm, st, g, tl, wk)
    type(params_t), intent(in) :: prm      !! parameters (fields, laws, basis)
    type(state_t), intent(in) :: st        !! state (particles, walls)
    type(grid_t), intent(in) :: g          !! grid (masses)
    type(tiles_t), intent(in) :: tl        !! live spans
    type(work_t), intent(inout) :: wk      !! basis cache; the contact work arrays
    if (prm%nf < 2) return
    call find_nodes(g, tl, prm%nf, wk%fc)
    call field_gradients(prm, st%p, g, wk)
    call find_pairs(prm, st, g, wk%fc)
    call surface_gaps(prm, st%p, g, wk)
    call tied_off(prm, st, g, wk%fc)
  end subroutine body_contact_detect

  !> 'bonded' bodies (mpm_body_tie): no contact law between them at the nodes of their tied
  !! surfaces (body_tie_nodes): there the ties hold the surfaces, pressed or pulled.
  subroutine tied_off(prm, st, g, fc)
    type(params_t), intent(in) :: prm      !! parameters (ties, fields)
    type(state_t), intent(in) :: st        !! state (corners)
    type(grid_t), intent(in) :: g          !! grid
    type(field_contact_t), intent(inout) :: fc  !! pair entries: laws
    integer :: e, ba, bb
    if (prm%ties%n == 0 .or. fc%npn == 0) return
    if (allocated(fc%tied)) then
      if (size(fc%tied) /= g%nn) deallocate(fc%tied)
    end if
    if (.not. allocated(fc%tied)) allocate(fc%tied(g%nn))
    fc%tied = .false.
    call body_tie_nodes(prm%ties, st%p%xc, g%origin, g%h, g%nx, g%ny, fc%tied)
    do e = 1, fc%npn
      ba = prm%field_body(fc%pn_a(e))
      bb = prm%field_body(fc%pn_b(e))
      if (ba == bb .or. fc%pn_law(e) /= CONTACT_BONDED) cycle
      if (fc%tied(fc%node(fc%pn_cn(e)))) fc%pn_law(e) = 0
    end do
  end subroutine tied_off

  !> The contact nodes: live nodes where two fields or more have mass above the cut-off.
  subroutine find_nodes(g, tl, nf, fc)
    type(grid_t), intent(in) :: g          !! grid
    type(tiles_t), intent(in) :: tl        !! live spans
    integer, intent(in) :: nf              !! fields
    type(field_contact_t), intent(inout) :: fc  !! contact nodes
    integer :: k, i0, i1, j0, j1, i, j, n0, f, cnt
    if (allocated(fc%cmap)) then
      if (size(fc%cmap) /= g%nn) deallocate(fc%cmap)
    end if
    if (.not. allocated(fc%cmap)) then
      allocate(fc%cmap(g%nn))
      fc%cmap = 0
    else
      fc%cmap(fc%node(1:fc%ncn)) = 0
    end if
    fc%ncn = 0
    call field_contact_reserve(fc, nf, 64, 64)
    do k = 1, tl%nspan
      call tiles_span(tl, k, i0, i1, j0, j1)
      do j = j0, j1
        do i = i0, i1
          n0 = 1 + i + g%nx*j
          cnt = 0
          do f = 0, nf - 1
            if (g%mass(n0 + f*g%nn) > g%mass_cut) cnt = cnt + 1
          end do
          if (cnt < 2) cycle
          call field_contact_reserve(fc, nf, fc%ncn + 1, 0)
          fc%ncn = fc%ncn + 1
          fc%node(fc%ncn) = n0
          fc%cmap(n0) = fc%ncn
        end do
      end do
    end do
  end subroutine find_nodes

  !> The first moment sum_p phi_ip m_p x_p of every field at the contact nodes (its local centre
  !! of mass times its node mass), and the particles that touch them.
  subroutine field_gradients(prm, p, g, wk)
    type(params_t), intent(in) :: prm      !! parameters (fields)
    type(particles_t), intent(in) :: p     !! particles
    type(grid_t), intent(in) :: g          !! grid
    type(work_t), intent(inout) :: wk      !! basis cache; gradients, particle list
    integer :: ip, a, b, kk, c, nb, k, lo(2), hi(2)
    logical :: touched
    associate (fc => wk%fc)
      fc%grad(:, :, 1:fc%ncn) = 0.0_wp
      fc%nplist = 0
      if (fc%ncn == 0) return
      if (.not. allocated(fc%plist)) allocate(fc%plist(p%np))
      nb = wk%nb
      ! the node range of the contact nodes: a particle whose block lies outside it touches
      ! none (most particles; the contact map is read only for the others)
      lo = huge(1)
      hi = -huge(1)
      do k = 1, fc%ncn
        lo = min(lo, [mod(fc%node(k) - 1, g%nx), (fc%node(k) - 1)/g%nx])
        hi = max(hi, [mod(fc%node(k) - 1, g%nx), (fc%node(k) - 1)/g%nx])
      end do
      do ip = 1, p%np
        if (wk%blk(1, ip) > hi(1) .or. wk%blk(1, ip) + nb - 1 < lo(1) .or. &
            wk%blk(2, ip) > hi(2) .or. wk%blk(2, ip) + nb - 1 < lo(2)) cycle
        touched = .false.
        do b = 0, nb - 1
          do a = 0, nb - 1
            kk = 1 + a + nb*b
            c = fc%cmap(1 + wk%blk(1, ip) + a + g%nx*(wk%blk(2, ip) + b))
            if (c == 0) cycle
            if (wk%w(kk, ip) == 0.0_wp .and. all(wk%gw(:, kk, ip) == 0.0_wp)) cycle
            fc%grad(:, prm%field(ip), c) = fc%grad(:, prm%field(ip), c) + &
                                           (wk%w(kk, ip)*p%mass(ip))*p%x(:, ip)
            touched = .true.
          end do
        end do
        if (touched) then
          fc%nplist = fc%nplist + 1
          fc%plist(fc%nplist) = ip
        end if
      end do
    end associate
  end subroutine field_gradients

  !> The pair entries: at each contact node every pair of fields with mass there whose bodies
  !! have a law between them, with its normal (between the fields' local centres of mass; on
  !! a mirror plane its component across the plane dropped, as the plane holds the node in
  !! that direction).
  subroutine find_pairs(prm, st, g, fc)
    type(params_t), intent(in) :: prm      !! parameters (fields, laws)
    type(state_t), intent(in) :: st        !! state (walls)
    type(grid_t), intent(in) :: g          !! grid
    type(field_contact_t), intent(inout) :: fc  !! pair entries
    integer :: c, a, b, cnt, npn, ba, bb, n0, iw
    real(wp) :: nv(2), len, xn(2), m(2)
    logical :: has(prm%nf), fixed
    npn = 0
    do c = 1, fc%ncn
      cnt = 0
      do a = 1, prm%nf
        if (g%mass(fc%node(c) + g%nn*(a - 1)) > g%mass_cut) cnt = cnt + 1
      end do
      npn = npn + (cnt*(cnt - 1))/2
    end do
    call field_contact_reserve(fc, prm%nf, fc%ncn, npn)
    fc%npn = 0
    do c = 1, fc%ncn
      fc%first(c) = fc%npn + 1
      n0 = fc%node(c)
      do a = 1, prm%nf
        has(a) = g%mass(n0 + g%nn*(a - 1)) > g%mass_cut
      end do
      xn(1) = g%origin(1) + g%h*real(mod(n0 - 1, g%nx), wp)
      xn(2) = g%origin(2) + g%h*real((n0 - 1)/g%nx, wp)
      do a = 1, prm%nf - 1
        if (.not. has(a)) cycle
        do b = a + 1, prm%nf
          if (.not. has(b)) cycle
          ba = prm%field_body(a)
          bb = prm%field_body(b)
          if (prm%pair_law(ba, bb) == 0) cycle
          ! the direction from a's local centre of mass at the node to b's
          nv = fc%grad(:, b, c)/g%mass(n0 + g%nn*(b - 1)) - &
               fc%grad(:, a, c)/g%mass(n0 + g%nn*(a - 1))
          fixed = .false.
          do iw = 1, st%nwall
            if (st%walls(iw)%contact /= CONTACT_SLIP) cycle
            m = st%walls(iw)%normal
            if (dot_product(xn - st%walls(iw)%point, m) > 1.0e-6_wp*g%h) cycle
            nv = nv - dot_product(nv, m)*m
            fixed = .true.
          end do
          len = sqrt(nv(1)**2 + nv(2)**2)
          if (.not. len > 1.0e-9_wp*g%h) cycle
          fc%npn = fc%npn + 1
          fc%pn_cn(fc%npn) = c
          fc%pn_a(fc%npn) = a
          fc%pn_b(fc%npn) = b
          fc%pn_law(fc%npn) = prm%pair_law(ba, bb)
          fc%pn_mu(fc%npn) = prm%pair_mu(ba, bb)
          fc%pn_pair(fc%npn) = 0
          if (ba /= bb) fc%pn_pair(fc%npn) = pair_index(ba, bb, prm%nbody)
          fc%pn_n(:, fc%npn) = nv/len
          fc%pn_fixed(fc%npn) = fixed
        end do
      end do
    end do
    fc%first(fc%ncn + 1) = fc%npn + 1
  end subroutine find_pairs

  !> The normal and gap of every pair entry from the two surfaces near its node: the domain
  !! corners of a's and b's particles that touch the node, within a cell of it along the
  !! surface (across the centre-of-mass normal); the normal is the direction that separates
  !! the two sets the most (separating_normal), the gap their distance along it.
  subroutine surface_gaps(prm, p, g, wk)
    type(params_t), intent(in) :: prm      !! parameters (fields, basis)
    type(particles_t), intent(in) :: p     !! particles
    type(grid_t), intent(in) :: g          !! grid
    type(work_t), intent(inout) :: wk      !! basis cache; normals and gaps
    integer :: e, k0, k1
    associate (fc => wk%fc)
      call gather_corners(prm, p, g, wk, .false.)
      call gather_corners(prm, p, g, wk, .true.)
      fc%gap_min = no_gap
      do e = 1, fc%npn
        k0 = fc%cq_first(e)
        k1 = fc%cq_first(e + 1) - 1
        if (any(fc%cq_b(k0:k1)) .and. .not. all(fc%cq_b(k0:k1))) then
          ! the two halves of one ring (self-contact) keep the centre-of-mass normal
          if (.not. fc%pn_fixed(e) .and. prm%field_body(fc%pn_a(e)) /= &
              prm%field_body(fc%pn_b(e))) call separating_normal(fc%cq(:, k0:k1), &
                                                     fc%cq_b(k0:k1), sep_eps*g%h, fc%pn_n(:, e))
          call extremes(fc%cq(:, k0:k1), fc%cq_b(k0:k1), fc%pn_n(:, e), fc%pn_ext(:, e))
          fc%pn_gap(e) = fc%pn_ext(2, e) - fc%pn_ext(1, e)
        else
          fc%pn_ext(:, e) = [-huge(1.0_wp), huge(1.0_wp)]
          fc%pn_gap(e) = no_gap
        end if
        fc%gap_min = min(fc%gap_min, fc%pn_gap(e))
      end do
    end associate
  end subroutine surface_gaps

  !> The surface corners of every pair entry (cq, cq_b, cq_first): the domain corners of a's
  !! and b's particles that touch the entry's node, within a cell of the node along the
  !! surface (across the entry's normal). First pass (fill false) counts, second fills.
  subroutine gather_corners(prm, p, g, wk, fill)
    type(params_t), intent(in) :: prm      !! parameters (fields, basis)
    type(particles_t), intent(in) :: p     !! particles
    type(grid_t), intent(in) :: g          !! grid
    type(work_t), intent(inout) :: wk      !! basis cache; surface corners
    logical, intent(in) :: fill            !! second pass: store the corners
    integer :: k, ip, f, a, b, kk, c, e, nb, q, slot, mark, id
    real(wp) :: xq(2, 4), xn(2)
    logical :: shared
    associate (fc => wk%fc)
      ! CPDI2's corners are shared by up to four particles: each is gathered once per entry
      ! and side, as far as its last n_marks entries remember (the extremes are the same
      ! without the repeats, which cost 42 % of a nested-tube crush's time in
      ! separating_normal)
      shared = prm%basis == BASIS_CPDI2
      if (shared) then
        if (allocated(fc%cq_mark)) then
          if (size(fc%cq_mark, 2) < p%nc) deallocate(fc%cq_mark)
        end if
        if (.not. allocated(fc%cq_mark)) allocate(fc%cq_mark(n_marks, p%nc))
        fc%cq_mark = 0
      end if
      if (.not. fill) then
        fc%cq_first(1:fc%npn + 1) = 0          ! entry e counts in cq_first(e + 1)
      else
        fc%cq_first(1) = 1                     ! counts -> first corner of each entry, then
        do e = 1, fc%npn                       ! cq_first(e + 1) is e's next free slot
          fc%cq_first(e + 1) = fc%cq_first(e) + fc%cq_first(e + 1)
        end do
        if (allocated(fc%cq)) then
          if (size(fc%cq_b) < fc%cq_first(fc%npn + 1)) deallocate(fc%cq, fc%cq_b)
        end if
        if (.not. allocated(fc%cq)) allocate(fc%cq(2, 2*fc%cq_first(fc%npn + 1)), &
                                             fc%cq_b(2*fc%cq_first(fc%npn + 1)))
        fc%cq_first(2:fc%npn + 1) = fc%cq_first(1:fc%npn)
      end if
      nb = wk%nb
      do k = 1, fc%nplist
        ip = fc%plist(k)
        f = prm%field(ip)
        xq = particle_corners(p, ip, prm%basis, deformed=.true.)
        do b = 0, nb - 1
          do a = 0, nb - 1
            kk = 1 + a + nb*b
            if (wk%w(kk, ip) == 0.0_wp .and. all(wk%gw(:, kk, ip) == 0.0_wp)) cycle
            c = fc%cmap(1 + wk%blk(1, ip) + a + g%nx*(wk%blk(2, ip) + b))
            if (c == 0) cycle
            xn(1) = g%origin(1) + g%h*real(wk%blk(1, ip) + a, wp)
            xn(2) = g%origin(2) + g%h*real(wk%blk(2, ip) + b, wp)
            do e = fc%first(c), fc%first(c + 1) - 1
              if (fc%pn_a(e) /= f .and. fc%pn_b(e) /= f) cycle
              mark = merge(-e, e, fc%pn_b(e) == f)
              do q = 1, 4
                if (shared) then
                  if (any(fc%cq_mark(:, p%corner(q, ip)) == mark)) cycle
                end if
                ! only the corners within a cell of the node along the surface
                if (abs(fc%pn_n(2, e)*(xq(1, q) - xn(1)) - fc%pn_n(1, e)*(xq(2, q) - xn(2))) &
                    > tang_window*g%h) cycle
                if (shared) then                 ! remembered in the oldest of its slots
                  id = p%corner(q, ip)
                  fc%cq_mark(:, id) = eoshift(fc%cq_mark(:, id), -1, mark)
                end if
                if (.not. fill) then
                  fc%cq_first(e + 1) = fc%cq_first(e + 1) + 1
                else
                  slot = fc%cq_first(e + 1)
                  fc%cq(:, slot) = xq(:, q)
                  fc%cq_b(slot) = fc%pn_b(e) == f
                  fc%cq_first(e + 1) = slot + 1
                end if
              end do
            end do
          end do
        end do
      end do
    end associate
  end subroutine gather_corners

  !> a's surface along n (the largest x . n over its corners) and b's (the smallest).
  pure subroutine extremes(q, isb, n, ext)
    real(wp), intent(in) :: q(:,:)         !! corners (2, k) [m]
    logical, intent(in) :: isb(:)          !! b's corner (k)
    real(wp), intent(in) :: n(2)           !! unit normal from a into b [-]
    real(wp), intent(out) :: ext(2)        !! a's and b's surface along n [m]
    real(wp) :: d
    integer :: k
    ext = [-huge(1.0_wp), huge(1.0_wp)]
    do k = 1, size(isb)
      d = n(1)*q(1, k) + n(2)*q(2, k)
      if (isb(k)) then
        ext(2) = min(ext(2), d)
      else
        ext(1) = max(ext(1), d)
      end if
    end do
  end subroutine extremes

  !> The direction that separates b's corners from a's the most: the unit n within
  !! max_turn of the given one (the centre-of-mass normal) that maximises min_b x . n -
  !! max_a x . n (golden-section search on the angle). Two surfaces that touch give their
  !! common tangent's normal (a ring on a flat block: the block's normal), where the
  !! centre-of-mass normal tilts with the part of the curved surface near the node.
  !! The choice treats both turning senses alike, so that the mirror image of a pair of
  !! surfaces gets the mirror image of the normal: the search runs once turning each way and
  !! takes the better end, or the mean of the two if they separate equally well (within eps);
  !! and n turns only if that gains more than eps over the given normal. Where two surfaces
  !! overlap a little, min_b x . n - max_a x . n is largest at two turns of opposite sense
  !! that gain next to nothing (a corner of b just behind one of a: their separation along n
  !! is -d cos(phi)), and a single search (which breaks ties towards one sense) then turned
  !! the normal one way at the first touch of two mirror-image rings and, by round-off, at
  !! some nodes later: the lower ring of two colliding head-on took 8.9 % more plastic work
  !! than the upper one by 0.5 ms (two_rings.nml at fbae066; docs/scenes.md).
  pure subroutine separating_normal(q, isb, eps, n)
    real(wp), intent(in) :: q(:,:)         !! corners (2, k) [m]
    logical, intent(in) :: isb(:)          !! b's corner (k)
    real(wp), intent(in) :: eps            !! separations closer than this are equal [m]
    real(wp), intent(inout) :: n(2)        !! unit normal from a into b: in, the initial
                                           !! one; out, the separating one [-]
    real(wp), parameter :: max_turn = 1.0471975511965976_wp  !! pi/3 [rad]
    real(wp), parameter :: tol = 1.0e-7_wp !! angle tolerance [rad]
    real(wp), parameter :: gr = 0.6180339887498949_wp  !! golden ratio - 1
    real(wp) :: n0(2), t0(2), xa, xb, fa, fb, x
    n0 = n
    t0 = [-n0(2), n0(1)]
    xa = golden(1.0_wp)                    ! turning from n0 towards t0 first ...
    xb = -golden(-1.0_wp)                  ! ... and towards -t0: the same search mirrored
    fa = sep(xa)
    fb = sep(xb)
    if (fa > fb + eps) then
      x = xa
    else if (fb > fa + eps) then
      x = xb
    else
      x = 0.5_wp*(xa + xb)
    end if
    if (sep(x) > sep(0.0_wp) + eps) then
      n = cos(x)*n0 + sin(x)*t0
      n = n/sqrt(n(1)**2 + n(2)**2)
    end if
  contains
    !> The turn phi in [-max_turn, max_turn] that maximises sep(s phi), to tol (golden
    !! section; where the two inner points separate equally it keeps the lower part).
    pure real(wp) function golden(s) result(phi)
      real(wp), intent(in) :: s            !! 1 or -1: the sense of the turn [-]
      real(wp) :: lo, hi, x1, x2, f1, f2
      lo = -max_turn
      hi = max_turn
      x1 = hi - gr*(hi - lo)
      x2 = lo + gr*(hi - lo)
      f1 = sep(s*x1)
      f2 = sep(s*x2)
      do while (hi - lo > tol)
        if (f1 < f2) then
          lo = x1
          x1 = x2
          f1 = f2
          x2 = lo + gr*(hi - lo)
          f2 = sep(s*x2)
        else
          hi = x2
          x2 = x1
          f2 = f1
          x1 = hi - gr*(hi - lo)
          f1 = sep(s*x1)
        end if
      end do
      phi = 0.5_wp*(lo + hi)
    end function golden

    !> min_b x . n - max_a x . n along n turned by phi from n0 [m].
    pure real(wp) function sep(phi)
      real(wp), intent(in) :: phi          !! turn from n0 [rad]
      real(wp) :: e(2)
      call extremes(q, isb, cos(phi)*n0 + sin(phi)*t0, e)
      sep = e(2) - e(1)
    end function sep
  end subroutine separating_normal

  !> The contact law at every pair entry on the node velocities (mpm_contact_law). With record
  !! (step 3) the velocity changes also enter dvel (FLIP sees the contact) and the impulses
  !! of the pairs of bodies are summed for the history. Without (the MUSL re-map, whose
  !! velocities move the domains and deform the particles but carry no momentum) only the
  !! normal part acts: friction there would let a body roll on the other with no friction
  !! force on its momentum (measured: a ring on an incline with mu = 0.1 accelerated as if
  !! frictionless while its domains rolled).
  subroutine body_contact_apply(prm, g, wk, dt, record)
    type(params_t), intent(in) :: prm      !! parameters (fields)
    type(grid_t), intent(inout) :: g       !! grid: velocities (and their changes)
    type(work_t), intent(inout) :: wk      !! pair entries; the pairs' impulses
    real(wp), intent(in) :: dt             !! time step [s]
    logical, intent(in) :: record          !! step 3: dvel and impulses
    integer :: e, n0, na, nb, law
    real(wp) :: j(2), pn, allow
    if (prm%nf < 2) return
    associate (fc => wk%fc)
      if (record) then
        if (.not. allocated(fc%pair_imp)) allocate(fc%pair_imp(3, prm%npair))
        fc%pair_imp = 0.0_wp
      end if
      do e = 1, fc%npn
        n0 = fc%node(fc%pn_cn(e))
        na = n0 + g%nn*(fc%pn_a(e) - 1)
        nb = n0 + g%nn*(fc%pn_b(e) - 1)
        allow = max(fc%pn_gap(e), 0.0_wp)/dt
        law = fc%pn_law(e)
        if (record) fc%pn_j(:, e) = 0.0_wp
        if (.not. record) fc%pn_jd(:, e) = 0.0_wp     ! (USF, MUSL: the deformation reads these)
        if (law == 0) cycle                            ! welded (mpm_self_contact)
        if (.not. record) law = CONTACT_FRICTIONLESS   ! the re-map: no friction (below)
        call contact_law_impulse(law, fc%pn_mu(e), g%mass(na), g%mass(nb), &
                                 g%vel(:, na), g%vel(:, nb), fc%pn_n(:, e), allow, j, pn)
        if (record) then                     ! for body_contact_loss
          if (pn > 0.0_wp) fc%pn_j(:, e) = j
          fc%pn_dv0(:, e) = g%mom(:, na)/g%mass(na) - g%mom(:, nb)/g%mass(nb)
        end if
        if (.not. record .and. pn > 0.0_wp) fc%pn_jd(:, e) = j
        if (.not. pn > 0.0_wp) cycle
        g%vel(:, na) = g%vel(:, na) + j/g%mass(na)
        g%vel(:, nb) = g%vel(:, nb) - j/g%mass(nb)
        if (.not. record) cycle
        g%dvel(:, na) = g%dvel(:, na) + j/g%mass(na)
        g%dvel(:, nb) = g%dvel(:, nb) - j/g%mass(nb)
        call add_pair(prm, fc, e, j, pn)
      end do
    end associate
  end subroutine body_contact_apply

  !> End of a step: the energy the contact between the fields took from the body over the
  !! step, added to st%e_contact_loss. Its velocity changes act twice (docs/method.md,
  !! "Energies"):
  !! - on the particles' motion: their kinetic energy changes by sum_p m_p vbar_p . dv_p
  !!   over a step (vbar_p the mean of the old and new velocity, dv_p = sum_i phi_ip dv_i
  !!   their change), exactly, so the share of the contact's changes j / m_a and -j / m_b at
  !!   an entry is j . (vbar_a - vbar_b), vbar_f = (p_f^old + p_f^new) / (2 m_f) with p_f =
  !!   sum_p phi_ip m_p v_p the field's momentum at the node before the step (its P2G) and
  !!   after it (the new particle velocities mapped back);
  !! - on the deformation: the velocities the strain update reads carry the contact's
  !!   changes jd / m_a, -jd / m_b (USF: before the stress update; MUSL: of the re-map), whose
  !!   strain work is that of the internal force f at the node, -dt jd . (f_a / m_a - f_b /
  !!   m_b) (to first order in dt: USF's f is the updated stress's).
  !! The loss is minus their sum. The velocity merge of multi-field contact is inelastic by
  !! construction: where it stops the approach of the two fields' nodes it takes their
  !! relative kinetic energy (two elastic rings colliding head-on at 10 m/s, h = t/4: 0.9 %
  !! of their energy at one particle per cell through the wall, 1.6 % at two;
  !! tests/test_body_contact.py). USL is left out: it reads the velocities of step 3 for the
  !! strain too, and its own loss (half the square of each step's velocity change, which the
  !! contact's change cancels where it holds a node) is not separable from the contact's;
  !! booked this way, its matrix rows of two rings showed a gain of 20 %
  !! (tests/test_scene_matrix.py), and their energy error keeps both losses.
  subroutine body_contact_loss(prm, st, g, wk, dt)
    type(params_t), intent(in) :: prm      !! parameters (fields)
    type(state_t), intent(inout) :: st     !! state: particles (new velocities); the loss
    type(grid_t), intent(in) :: g          !! grid (field masses, node forces)
    type(work_t), intent(inout) :: wk      !! basis cache; the step's entries and impulses
    real(wp), intent(in) :: dt             !! the step just taken [s]
    integer :: k, ip, a, b, kk, c, e, f, na, nb
    real(wp) :: loss, vb(2)
    if (prm%nf < 2 .or. prm%scheme == SCHEME_USL) return
    associate (fc => wk%fc)
      if (fc%npn == 0) return
      fc%mom1(:, :, 1:fc%ncn) = 0.0_wp
      do k = 1, fc%nplist
        ip = fc%plist(k)
        f = prm%field(ip)
        do b = 0, wk%nb - 1
          do a = 0, wk%nb - 1
            kk = 1 + a + wk%nb*b
            c = fc%cmap(1 + wk%blk(1, ip) + a + g%nx*(wk%blk(2, ip) + b))
            if (c == 0 .or. wk%w(kk, ip) == 0.0_wp) cycle
            fc%mom1(:, f, c) = fc%mom1(:, f, c) + (wk%w(kk, ip)*st%p%mass(ip))*st%p%v(:, ip)
          end do
        end do
      end do
      loss = 0.0_wp
      do e = 1, fc%npn
        c = fc%pn_cn(e)
        na = fc%node(c) + g%nn*(fc%pn_a(e) - 1)
        nb = fc%node(c) + g%nn*(fc%pn_b(e) - 1)
        if (any(fc%pn_j(:, e) /= 0.0_wp)) then
          vb = 0.5_wp*(fc%pn_dv0(:, e) + fc%mom1(:, fc%pn_a(e), c)/g%mass(na) &
                       - fc%mom1(:, fc%pn_b(e), c)/g%mass(nb))
          loss = loss - dot_product(fc%pn_j(:, e), vb)
        end if
        if (any(fc%pn_jd(:, e) /= 0.0_wp)) loss = loss + dt* &
          dot_product(fc%pn_jd(:, e), g%force(:, na)/g%mass(na) - g%force(:, nb)/g%mass(nb))
      end do
      st%e_contact_loss = st%e_contact_loss + loss
    end associate
  end subroutine body_contact_loss

  !> Add impulse j on field a (and normal impulse pn) of entry e to its pair of bodies.
  subroutine add_pair(prm, fc, e, j, pn)
    type(params_t), intent(in) :: prm      !! parameters (bodies of the fields)
    type(field_contact_t), intent(inout) :: fc  !! the pairs' impulses
    integer, intent(in) :: e               !! pair entry
    real(wp), intent(in) :: j(2)           !! impulse on field a [kg/s per m]
    real(wp), intent(in) :: pn             !! normal impulse [kg/s per m]
    integer :: ip
    ip = fc%pn_pair(e)
    if (ip == 0) return
    fc%pair_imp(1, ip) = fc%pair_imp(1, ip) + pn
    if (prm%field_body(fc%pn_a(e)) < prm%field_body(fc%pn_b(e))) then
      fc%pair_imp(2:3, ip) = fc%pair_imp(2:3, ip) + j        ! on the first body of the pair
    else
      fc%pair_imp(2:3, ip) = fc%pair_imp(2:3, ip) - j
    end if
  end subroutine add_pair

  !> End of a step: the pairs' impulses summed for the history, their force over the step.
  subroutine body_contact_reactions(prm, st, wk, dt)
    type(params_t), intent(in) :: prm      !! parameters (pairs)
    type(state_t), intent(inout) :: st     !! state: the pairs' sums
    type(work_t), intent(in) :: wk         !! the pairs' impulses of the step
    real(wp), intent(in) :: dt             !! the step just taken [s]
    if (prm%npair == 0 .or. .not. allocated(wk%fc%pair_imp)) return
    st%pair_acc = st%pair_acc + wk%fc%pair_imp
    st%pair_force = wk%fc%pair_imp/dt
    if (prm%ties%n == 0 .or. .not. allocated(wk%tie_imp)) return
    st%pair_acc = st%pair_acc + wk%tie_imp        ! 'bonded' bodies: their ties
    st%pair_force = st%pair_force + wk%tie_imp/dt
  end subroutine body_contact_reactions
end module mpm_body_contact
