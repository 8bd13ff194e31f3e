!> Self-contact of a ring (`&body self_contact = .true.`): the ring's upper and lower halves are
!! two contact fields of one body, welded along their seams and meeting elsewhere by the
!! contact law of mpm_body_contact, so that a tube crushed flat does not weld its inner walls.
! SPDX-License-Identifier: MIT
!
! One velocity field per body welds the inner walls of a crushed ring as soon as they share a
! node (a cell or more before their surfaces meet), and they never part. Here the ring is split
! by the line y = centre into its upper half (the body's first field) and its lower half (a
! second field, mpm_setup): the walls that meet in a crush between platens along y (top and
! bottom) are then always in different fields, and the multi-field contact of mpm_body_contact
! finds their surfaces and applies its law (frictionless) with separation. Where the halves are
! one piece of material, at the seams (the points of the ring on the line y = centre: both
! sides of a full ring, the side x > centre of a half ring), they must move as one field.
! The seam is Lagrangian: a particle is "bonded" when its centre at t = 0 lies within
! band = 2 h + 2 hmax of the line (hmax the body's largest particle half-size: at t = 0 every
! node that both halves' particles touch is touched only by bonded particles of both; a particle
! reaches one cell beyond its domain). At a node where both halves have mass and both have
! bonded particles, the two fields are welded: the velocity of each becomes their mass-weighted
! mean, which is the velocity one field would have had there (the grid update is linear in the
! momenta and forces), and in step 3 their velocity changes become the mass-weighted mean too,
! the FLIP increment of one field. Momentum is moved between the halves, never created. The
! contact law's entry of a welded node is switched off (law 0). Elsewhere the halves meet only
! through their surfaces, by the law: at the inner walls, and within a fold's lobe beyond the
! bonded band. The seams move with the material, so they stay at the lobes of a flattened ring.
! Why this and not surface detection within one field: one field cannot keep two walls apart
! that share a node (their velocities there are one), so a second field is needed where the
! walls meet, and with two fields the seam must be welded (Homel & Herbold 2017 and Nairn's
! cracks do the same with fields assigned per node from a damage or crack geometry; here the
! geometry is the ring's, known at t = 0). docs/method.md, "Self-contact".
module mpm_self_contact
  use mpm_kinds, only: wp
  use mpm_grid, only: grid_t
  use mpm_contact_law, only: field_contact_t
  implicit none
  private
  public :: self_weld_t, self_contact_split, self_contact_mark, self_contact_weld

  !> The welded nodes of a step.
  type :: self_weld_t
    integer :: nweld = 0                   !! welded (node, field a, field b) of the step
    integer, allocatable :: wn(:,:)        !! node id (of field 1), field a, field b (3, nweld)
    logical, allocatable :: bonded(:,:)    !! field f has bonded particles at contact node c
                                           !! (nf, ncn)
  end type self_weld_t

contains

  !> The second field of the rings with self-contact: the particles of body ib below its
  !! centre line (y < centre) go to field first(ib) + 1, and bond(ip) is the other half's
  !! field for the particles within the band of the seam, else 0.
  pure subroutine self_contact_split(x, half, body, self, center, first, h, field, bond)
    real(wp), intent(in) :: x(:,:)         !! particle positions at t = 0 (2, np) [m]
    real(wp), intent(in) :: half(:,:)      !! particle half-sizes (2, np) [m]
    integer, intent(in) :: body(:)         !! body of each particle (np)
    logical, intent(in) :: self(:)         !! self-contact of each body (nbody)
    real(wp), intent(in) :: center(:,:)    !! centre of each body (2, nbody) [m]
    integer, intent(in) :: first(:)        !! first field of each body (nbody)
    real(wp), intent(in) :: h              !! cell size [m]
    integer, intent(inout) :: field(:)     !! field of each particle (np)
    integer, intent(out) :: bond(:)        !! the field it is welded to, or 0 (np)
    integer :: ip, ib
    real(wp) :: band(size(self))
    band = 0.0_wp
    do ip = 1, size(body)
      ib = body(ip)
      if (self(ib)) band(ib) = max(band(ib), maxval(half(:, ip)))
    end do
    band = 2.0_wp*h + 2.0_wp*band
    bond = 0
    do ip = 1, size(body)
      ib = body(ip)
      if (.not. self(ib)) cycle
      if (x(2, ip) < center(2, ib)) then
        field(ip) = first(ib) + 1
        if (center(2, ib) - x(2, ip) < band(ib)) bond(ip) = first(ib)
      else
        field(ip) = first(ib)
        if (x(2, ip) - center(2, ib) < band(ib)) bond(ip) = first(ib) + 1
      end if
    end do
  end subroutine self_contact_split

  !> The welded nodes of the step (after mpm_body_contact's detection): the contact nodes where
  !! both halves of a self-contact ring have mass above the cut-off and bonded particles; their
  !! pair entries are switched off (law 0).
  subroutine self_contact_mark(field, bond, field_body, nb, blk, w, gw, g, fc, sw)
    integer, intent(in) :: field(:)        !! field of each particle (np)
    integer, intent(in) :: bond(:)         !! the field each particle is welded to, or 0 (np)
    integer, intent(in) :: field_body(:)   !! body of each field (nf)
    integer, intent(in) :: nb              !! nodes per direction of a particle's block
    integer, intent(in) :: blk(:,:)        !! lowest-left node of each block (2, np)
    real(wp), intent(in) :: w(:,:)         !! weights (nb nb, np)
    real(wp), intent(in) :: gw(:,:,:)      !! weight gradients (2, nb nb, np)
    type(grid_t), intent(in) :: g          !! grid (masses)
    type(field_contact_t), intent(inout) :: fc  !! contact nodes and pair entries
    type(self_weld_t), intent(inout) :: sw !! the welded nodes
    integer :: k, ip, a, b, kk, c, fa, fb, e, n0, nf, f, ng
    integer, allocatable :: grp(:)
    nf = size(field_body)
    sw%nweld = 0
    if (fc%ncn == 0) return
    if (allocated(sw%bonded)) then
      if (size(sw%bonded, 2) < fc%ncn) deallocate(sw%bonded)
    end if
    if (.not. allocated(sw%bonded)) allocate(sw%bonded(nf, max(fc%ncn, 64)))
    sw%bonded(:, 1:fc%ncn) = .false.
    do k = 1, fc%nplist
      ip = fc%plist(k)
      if (bond(ip) == 0) cycle
      do b = 0, nb - 1
        do a = 0, nb - 1
          kk = 1 + a + nb*b
          if (w(kk, ip) == 0.0_wp .and. all(gw(:, kk, ip) == 0.0_wp)) cycle
          c = fc%cmap(1 + blk(1, ip) + a + g%nx*(blk(2, ip) + b))
          if (c /= 0) sw%bonded(field(ip), c) = .true.
        end do
      end do
    end do
    allocate(grp(nf))
    do c = 1, fc%ncn
      n0 = fc%node(c)
      fa = 1
      do while (fa <= nf)                    ! the fields of one body are consecutive
        fb = fa
        do while (fb < nf)
          if (field_body(fb + 1) /= field_body(fa)) exit
          fb = fb + 1
        end do
        ng = 0                               ! its fields with bonded particles and mass here
        do f = fa, fb
          if (sw%bonded(f, c) .and. g%mass(n0 + g%nn*(f - 1)) > g%mass_cut) then
            ng = ng + 1
            grp(ng) = f
          end if
        end do
        if (ng >= 2) then
          do f = 2, ng
            call push_weld(sw, n0, grp(1), grp(f))
          end do
          do e = fc%first(c), fc%first(c + 1) - 1
            if (any(grp(1:ng) == fc%pn_a(e)) .and. any(grp(1:ng) == fc%pn_b(e))) fc%pn_law(e) = 0
          end do
        end if
        fa = fb + 1
      end do
    end do
  end subroutine self_contact_mark

  !> Append a welded node.
  subroutine push_weld(sw, n0, fa, fb)
    type(self_weld_t), intent(inout) :: sw !! the welded nodes
    integer, intent(in) :: n0, fa, fb      !! node, the two fields
    integer, allocatable :: t(:,:)
    if (.not. allocated(sw%wn)) allocate(sw%wn(3, 64))
    if (sw%nweld == size(sw%wn, 2)) then
      allocate(t(3, 2*size(sw%wn, 2)))
      t(:, 1:sw%nweld) = sw%wn(:, 1:sw%nweld)
      call move_alloc(t, sw%wn)
    end if
    sw%nweld = sw%nweld + 1
    sw%wn(:, sw%nweld) = [n0, fa, fb]
  end subroutine push_weld

  !> Weld the fields at the welded nodes: the velocities of a node's group (its entries with
  !! one first field) become their mass-weighted mean (and with record, step 3, the velocity
  !! changes that FLIP adds too).
  subroutine self_contact_weld(g, sw, record)
    type(grid_t), intent(inout) :: g       !! grid: velocities (and their changes)
    type(self_weld_t), intent(in) :: sw    !! the welded nodes
    logical, intent(in) :: record          !! step 3: also dvel
    integer :: k, k1, j, na, nb
    real(wp) :: ms, v(2), dv(2)
    k = 1
    do while (k <= sw%nweld)
      k1 = k                                 ! the group: entries k .. k1 with one node, field a
      do while (k1 < sw%nweld)
        if (sw%wn(1, k1 + 1) /= sw%wn(1, k) .or. sw%wn(2, k1 + 1) /= sw%wn(2, k)) exit
        k1 = k1 + 1
      end do
      na = sw%wn(1, k) + g%nn*(sw%wn(2, k) - 1)
      ms = g%mass(na)
      v = g%mass(na)*g%vel(:, na)
      dv = 0.0_wp
      if (record) dv = g%mass(na)*g%dvel(:, na)
      do j = k, k1
        nb = sw%wn(1, j) + g%nn*(sw%wn(3, j) - 1)
        v = v + g%mass(nb)*g%vel(:, nb)
        if (record) dv = dv + g%mass(nb)*g%dvel(:, nb)
        ms = ms + g%mass(nb)
      end do
      v = v/ms
      dv = dv/ms
      g%vel(:, na) = v
      if (record) g%dvel(:, na) = dv
      do j = k, k1
        nb = sw%wn(1, j) + g%nn*(sw%wn(3, j) - 1)
        g%vel(:, nb) = v
        if (record) g%dvel(:, nb) = dv
      end do
      k = k1 + 1
    end do
  end subroutine self_contact_weld
end module mpm_self_contact
