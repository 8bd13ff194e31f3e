!> Contact between velocity fields at one grid node (multi-field MPM): the laws 'frictionless',
!! 'coulomb' and 'stick' with separation, as the impulse that two fields exchange, and the
!! work arrays of the contact nodes of a step (mpm_body_contact fills and applies them).
! SPDX-License-Identifier: MIT
!
! Two fields a and b share a node with masses m_a, m_b and velocities v_a, v_b; n is the unit
! normal pointing from a into b, gap the distance between their surfaces along n (from the
! particle domains, mpm_body_contact). The surfaces close at the rate w = (v_a - v_b) . n.
! Within a step they may close the gap, no more: where w > max(gap, 0) / dt the fields are in
! contact and exchange the impulse that brings w down to that rate,
!
!     P_n = mu (w - max(gap, 0) / dt),     mu = m_a m_b / (m_a + m_b)  (the reduced mass),
!
! along -n on a and +n on b, with the tangential impulse of the law on the relative tangential
! velocity s = (v_a - v_b) - w n: none ('frictionless'), mu s ('stick'), or mu s bounded by
! friction P_n in length ('coulomb'). Where w <= max(gap, 0) / dt the fields move apart or
! have not met yet: nothing is exchanged, so bodies separate freely. The impulse on b is
! minus the one on a: momentum is exchanged, never created (Bardenhagen et al. 2000, 2001;
! docs/method.md, "Contact between bodies").
module mpm_contact_law
  use mpm_kinds, only: wp
  use mpm_constants, only: CONTACT_COULOMB, CONTACT_STICK, CONTACT_BONDED
  implicit none
  private
  public :: field_contact_t, contact_law_impulse, field_contact_reserve

  !> The contact nodes of a step and the field pairs that meet at them.
  type :: field_contact_t
    integer :: ncn = 0                     !! contact nodes (two fields or more with mass)
    integer, allocatable :: node(:)        !! node id (of field 1) of each contact node (ncn)
    integer, allocatable :: cmap(:)        !! contact node of each grid node, or 0 (nn)
    real(wp), allocatable :: grad(:,:,:)   !! first moment sum phi m_p x_p of each field (2, nf,
                                           !! ncn) [kg]
    integer, allocatable :: first(:)       !! first pair entry of each contact node (ncn + 1)
    integer :: npn = 0                     !! pair entries (one per node and pair of fields)
    integer, allocatable :: pn_a(:), pn_b(:)  !! the two fields of each entry (npn)
    integer, allocatable :: pn_cn(:)       !! contact node of each entry (npn)
    integer, allocatable :: pn_law(:)      !! CONTACT_* law of each entry (npn)
    integer, allocatable :: pn_pair(:)     !! pair of bodies (history columns) of each entry
    real(wp), allocatable :: pn_mu(:)      !! Coulomb coefficient of each entry (npn) [-]
    real(wp), allocatable :: pn_n(:,:)     !! unit normal from field a into b (2, npn) [-]
    real(wp), allocatable :: pn_ext(:,:)   !! a's surface along n (largest x . n) and b's
                                           !! (smallest x . n) (2, npn) [m]
    real(wp), allocatable :: pn_gap(:)     !! gap between the surfaces along n (npn) [m]
    logical, allocatable :: pn_fixed(:)    !! normal held by a mirror plane (npn)
    integer, allocatable :: cq_first(:)    !! first surface corner of each entry (npn + 1)
    real(wp), allocatable :: cq(:,:)       !! the entries' surface corners near their nodes
                                           !! (2, ncq) [m]
    logical, allocatable :: cq_b(:)        !! the corner is b's (else a's) (ncq)
    integer, allocatable :: cq_mark(:,:)   !! CPDI2: the last entries (b's: minus them) each
                                           !! shared domain corner was gathered for (8, nc)
    integer :: nplist = 0                  !! particles whose block holds a contact node
    integer, allocatable :: plist(:)       !! those particles (np)
    real(wp), allocatable :: pair_imp(:,:) !! per pair of bodies this step: normal impulse and
                                           !! the impulse on the first body (3, npair) [kg/s/m]
    real(wp), allocatable :: pn_j(:,:)     !! impulse on field a of each entry in step 3, or 0
                                           !! (2, npn) [kg/s per m]
    real(wp), allocatable :: pn_dv0(:,:)   !! v_a - v_b at the step's start, mom / m of the
                                           !! P2G (2, npn) [m/s]
    real(wp), allocatable :: pn_jd(:,:)    !! impulse on field a of each entry in the velocities
                                           !! the deformation update reads, or 0 (2, npn)
                                           !! [kg/s per m]
    real(wp), allocatable :: mom1(:,:,:)   !! sum_p phi_ip m_p v_p of each field at the contact
                                           !! nodes after G2P (2, nf, ncn) [kg m/s per m]
    real(wp) :: gap_min = 0.0_wp           !! the smallest gap of the step's entries [m]
    logical, allocatable :: tied(:)        !! 'bonded' bodies: the nodes of the tied surfaces
                                           !! this step (mpm_body_tie, body_tie_nodes) (nn)
  end type field_contact_t

contains

  !> The impulse exchanged by fields a and b at a node under `law`: j is the impulse on a
  !! (b receives -j), pn the normal impulse (>= 0; 0 when they are not in contact) [kg m/s
  !! per m]. allow = max(gap, 0) / dt, the closing rate the gap admits [m/s].
  pure subroutine contact_law_impulse(law, friction, ma, mb, va, vb, n, allow, j, pn)
    integer, intent(in) :: law             !! CONTACT_* code
    real(wp), intent(in) :: friction       !! Coulomb coefficient [-]
    real(wp), intent(in) :: ma, mb         !! node masses of the fields [kg/m]
    real(wp), intent(in) :: va(2), vb(2)   !! node velocities of the fields [m/s]
    real(wp), intent(in) :: n(2)           !! unit normal from a into b [-]
    real(wp), intent(in) :: allow          !! closing rate admitted by the gap [m/s]
    real(wp), intent(out) :: j(2)          !! impulse on a [kg/s per m]
    real(wp), intent(out) :: pn            !! normal impulse [kg/s per m]
    real(wp) :: w, mu, s(2), sl, pt
    j = 0.0_wp
    pn = 0.0_wp
    w = (va(1) - vb(1))*n(1) + (va(2) - vb(2))*n(2)
    if (.not. w > allow) return            ! apart, or not yet met: free
    mu = ma*mb/(ma + mb)
    pn = mu*(w - allow)
    j = -pn*n
    if (law /= CONTACT_COULOMB .and. law /= CONTACT_STICK .and. law /= CONTACT_BONDED) return
    s = (va - vb) - w*n                    ! relative tangential velocity
    sl = sqrt(s(1)**2 + s(2)**2)
    if (.not. sl > 0.0_wp) return
    pt = mu*sl                             ! the impulse that stops the slip
    if (law /= CONTACT_STICK) pt = min(pt, friction*pn)    ! 'bonded': where not tied
    j = j - (pt/sl)*s
  end subroutine contact_law_impulse

  !> Room for ncn contact nodes of nf fields and npn pair entries (kept between steps).
  subroutine field_contact_reserve(fc, nf, ncn, npn)
    type(field_contact_t), intent(inout) :: fc  !! work arrays
    integer, intent(in) :: nf              !! fields
    integer, intent(in) :: ncn             !! contact nodes
    integer, intent(in) :: npn             !! pair entries
    integer, allocatable :: ti(:)
    real(wp), allocatable :: tg(:,:,:)
    integer :: m
    if (.not. allocated(fc%node)) then
      allocate(fc%node(64), fc%grad(2, nf, 64), fc%mom1(2, nf, 64), fc%first(65))
      allocate(fc%pn_a(64), fc%pn_b(64), fc%pn_cn(64), fc%pn_law(64), fc%pn_pair(64), &
               fc%pn_mu(64), fc%pn_n(2, 64), fc%pn_ext(2, 64), fc%pn_gap(64), &
               fc%pn_fixed(64), fc%pn_j(2, 64), fc%pn_dv0(2, 64), fc%pn_jd(2, 64), &
               fc%cq_first(65))
    end if
    if (ncn > size(fc%node)) then
      m = max(ncn, 2*size(fc%node))
      allocate(ti(m))
      ti(1:fc%ncn) = fc%node(1:fc%ncn)
      call move_alloc(ti, fc%node)
      allocate(tg(2, nf, m))
      tg(:, :, 1:fc%ncn) = fc%grad(:, :, 1:fc%ncn)
      call move_alloc(tg, fc%grad)
      deallocate(fc%first, fc%mom1)
      allocate(fc%first(m + 1), fc%mom1(2, nf, m))
    end if
    if (npn > size(fc%pn_a)) then
      m = max(npn, 2*size(fc%pn_a))
      deallocate(fc%pn_a, fc%pn_b, fc%pn_cn, fc%pn_law, fc%pn_pair, fc%pn_mu, fc%pn_n, &
                 fc%pn_ext, fc%pn_gap, fc%pn_fixed, fc%pn_j, fc%pn_dv0, fc%pn_jd, fc%cq_first)
      allocate(fc%pn_a(m), fc%pn_b(m), fc%pn_cn(m), fc%pn_law(m), fc%pn_pair(m), &
               fc%pn_mu(m), fc%pn_n(2, m), fc%pn_ext(2, m), fc%pn_gap(m), fc%pn_fixed(m), &
               fc%pn_j(2, m), fc%pn_dv0(2, m), fc%pn_jd(2, m), fc%cq_first(m + 1))
    end if
  end subroutine field_contact_reserve
end module mpm_contact_law
