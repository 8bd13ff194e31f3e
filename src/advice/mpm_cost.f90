!> The wall time of a run, for `--check` and the report of the set-up: the particle-steps at the
!! throughput `make bench` measured per basis, corrected by what its single ring does not have:
!! a grid of another size per particle and velocity fields beyond the first (grid work per node
!! and field), the contact between fields (per pair entry: a node where two fields with a
!! contact law both have mass; between two bodies the surfaces' separating normal is searched
!! there, within a body not), the crushable foam's return map (per foam particle; more in plane
!! stress, where it iterates on the out-of-plane strain), F-bar (per particle) and a fixed cost
!! per step. Each term was fitted where its time goes (tools/advice_tables.py: the contact to
!! the P2G phase's timer, foam and F-bar to the stress phase's, the rest to the step's time).
! SPDX-License-Identifier: MIT
!
! The data are compiled in from generated tables (tools/advice_tables.py writes them):
! src/advice/mpm_bench_table.inc (make bench's particle-steps per second per basis, on 1 and 2
! threads) and src/advice/mpm_cost_table.inc (the terms' costs, fitted to the one-thread times
! of make bench-cost in docs/bench/cost_*.csv, docs/performance.md). The pair entries are
! counted at t = 0 from the particles' squares (the nodes of the cells their corners lie in);
! two bodies with a contact law are taken to touch, averaged over the run, along the share
! contact_keep of what touches at t = 0 (surfaces part as they deform) or the share
! contact_cover of the smaller one's surface nodes (contact that comes), the larger. On two threads the
! terms of parallel loops speed up as make bench's scenes do; the contact search and the fixed
! cost do not (serial).
module mpm_cost
  use mpm_kinds, only: wp
  use mpm_constants, only: basis_names, MODEL_FOAM, VOLUMETRIC_FBAR, VOLUMETRIC_FBARWALL, &
                           PLANE_STRESS
  use mpm_state, only: sim_t
  use mpm_strings, only: hms
  implicit none
  private
  public :: cost_counts_t, cost_counts, cost_case_counts, advice_wall_time, cost_step_seconds
  public :: contact_cover

  !> A row of the bench table: particle-steps per second on 1 and on 2 threads.
  type :: bench_row_t
    character(len=8) :: basis = ''
    real(wp) :: rate(2) = 0.0_wp
  end type bench_row_t

  include 'mpm_bench_table.inc'
  include 'mpm_cost_table.inc'

  real(wp), parameter :: long_run = 3600.0_wp  !! a run beyond this wants checkpoints [s]

  !> What a case has that the cost model counts (per step).
  type :: cost_counts_t
    real(wp) :: particles = 0.0_wp         !! particles [-]
    real(wp) :: nodes = 0.0_wp             !! grid nodes [-]
    integer :: fields = 1                  !! velocity fields [-]
    real(wp) :: foam = 0.0_wp              !! particles of a foam material [-]
    real(wp) :: foam_plane = 0.0_wp        !! of them in plane stress [-]
    real(wp) :: fbar = 0.0_wp              !! particles under F-bar [-]
    real(wp) :: touching = 0.0_wp          !! pair entries between bodies at t = 0 [-]
    real(wp) :: facing = 0.0_wp            !! surface nodes of the smaller body of each pair
                                           !! of bodies with a law, summed [-]
    real(wp) :: contact = 0.0_wp           !! pair entries between bodies, mean of a run: per
                                           !! pair contact_keep x those at t = 0 or
                                           !! contact_cover x its facing nodes, the larger [-]
    real(wp), allocatable :: pair_touch(:) !! per pair of bodies with a law: its entries ...
    real(wp), allocatable :: pair_face(:)  !! ... and its facing nodes at t = 0 [-]
    real(wp) :: self = 0.0_wp              !! pair entries within a body at t = 0 [-]
  end type cost_counts_t

contains

  !> The counts of a simulation set up at t = 0 (cost_counts).
  function cost_case_counts(s) result(c)
    type(sim_t), intent(in) :: s           !! the simulation at t = 0
    type(cost_counts_t) :: c
    logical :: foam(s%p%np)
    integer :: ip
    do ip = 1, s%p%np
      foam(ip) = s%prm%mats(s%p%mat(ip))%model_id == MODEL_FOAM
    end do
    c%particles = real(s%p%np, wp)
    c%nodes = real(s%g%nn, wp)
    c%fields = s%prm%nf
    c%foam = real(count(foam), wp)
    if (s%prm%plane == PLANE_STRESS) c%foam_plane = c%foam
    if (s%prm%volumetric == VOLUMETRIC_FBAR .or. s%prm%volumetric == VOLUMETRIC_FBARWALL) &
      c%fbar = c%particles
    if (s%prm%nf < 2) return
    call cost_counts(s%p%x(:, 1:s%p%np), s%p%half(:, 1:s%p%np), s%prm%field(1:s%p%np), &
                     s%prm%field_body, s%prm%pair_law, s%g%origin, s%g%h, s%g%nx, &
                     s%g%ny, c)
  end function cost_case_counts

  !> The counts of a case at t = 0: every particle's square (x -+ half) marks the nodes of the
  !! cells its corners lie in, for its field; a node marked for two fields whose bodies have a
  !! contact law is a pair entry per such pair (between two bodies, or within one: self
  !! contact); a body's surface nodes are its marked nodes with a neighbour it does not mark.
  pure subroutine cost_counts(x, half, field, field_body, pair_law, origin, h, nx, ny, c)
    real(wp), intent(in) :: x(:,:)         !! particle positions (2, np) [m]
    real(wp), intent(in) :: half(:,:)      !! particle half sizes (2, np) [m]
    integer, intent(in) :: field(:)        !! velocity field of each particle (np)
    integer, intent(in) :: field_body(:)   !! body of each field (nf)
    integer, intent(in) :: pair_law(:,:)   !! contact law between two bodies, 0 none (nb, nb)
    real(wp), intent(in) :: origin(2)      !! grid origin [m]
    real(wp), intent(in) :: h              !! cell size [m]
    integer, intent(in) :: nx, ny          !! nodes along x and y
    type(cost_counts_t), intent(inout) :: c  !! in: particles, nodes, fields, foam; out: contact
    logical, allocatable :: marked(:,:), body_node(:,:)
    integer :: nf, nbody, ip, q, i, j, n, a, b, ba, bb
    integer, allocatable :: surf(:)
    real(wp), allocatable :: touch(:,:)
    real(wp) :: corner(2)
    integer :: npair
    nf = size(field_body)
    nbody = size(pair_law, 1)
    c%touching = 0.0_wp
    c%facing = 0.0_wp
    c%contact = 0.0_wp
    c%self = 0.0_wp
    c%pair_touch = [real(wp) ::]
    c%pair_face = [real(wp) ::]
    if (nf < 2 .or. nx < 2 .or. ny < 2) return
    allocate(marked(nx*ny, nf), body_node(nx*ny, nbody), surf(nbody), touch(nbody, nbody))
    marked = .false.
    do ip = 1, size(field)
      do q = 0, 3
        corner = x(:, ip) + half(:, ip)*[real(2*mod(q, 2) - 1, wp), real(2*(q/2) - 1, wp)]
        i = min(max(floor((corner(1) - origin(1))/h), 0), nx - 2)
        j = min(max(floor((corner(2) - origin(2))/h), 0), ny - 2)
        n = 1 + i + nx*j
        marked([n, n + 1, n + nx, n + nx + 1], field(ip)) = .true.
      end do
    end do
    touch = 0.0_wp
    do n = 1, nx*ny
      do a = 1, nf - 1
        if (.not. marked(n, a)) cycle
        do b = a + 1, nf
          if (.not. marked(n, b)) cycle
          ba = field_body(a)
          bb = field_body(b)
          if (pair_law(ba, bb) == 0) cycle
          if (ba == bb) then
            c%self = c%self + 1.0_wp
          else
            c%touching = c%touching + 1.0_wp
            touch(min(ba, bb), max(ba, bb)) = touch(min(ba, bb), max(ba, bb)) + 1.0_wp
          end if
        end do
      end do
    end do
    ! the bodies' surface nodes (a marked node beside one the body does not mark)
    body_node = .false.
    do a = 1, nf
      body_node(:, field_body(a)) = body_node(:, field_body(a)) .or. marked(:, a)
    end do
    surf = 0
    do b = 1, nbody
      do j = 0, ny - 1
        do i = 0, nx - 1
          n = 1 + i + nx*j
          if (.not. body_node(n, b)) cycle
          if (i == 0 .or. i == nx - 1 .or. j == 0 .or. j == ny - 1) cycle
          if (.not. all(body_node([n - 1, n + 1, n - nx, n + nx], b))) surf(b) = surf(b) + 1
        end do
      end do
    end do
    npair = count([((pair_law(ba, bb) /= 0 .and. bb > ba, bb = 1, nbody), ba = 1, nbody)])
    deallocate(c%pair_touch, c%pair_face)
    allocate(c%pair_touch(npair), c%pair_face(npair))
    npair = 0
    do ba = 1, nbody - 1
      do bb = ba + 1, nbody
        if (pair_law(ba, bb) == 0) cycle
        npair = npair + 1
        c%pair_touch(npair) = touch(ba, bb)
        c%pair_face(npair) = real(min(surf(ba), surf(bb)), wp)
      end do
    end do
    c%facing = sum(c%pair_face)
    c%contact = sum(max(contact_keep*c%pair_touch, contact_cover*c%pair_face))
  end subroutine cost_counts

  !> The wall time of one step on `threads` threads of the release build [s] (0 where make
  !! bench has not measured the basis), and the bench's rate for the basis [particle-steps/s].
  pure subroutine cost_step_seconds(c, basis, threads, seconds, bench_rate)
    type(cost_counts_t), intent(in) :: c   !! the case's counts
    integer, intent(in) :: basis           !! BASIS_* code
    integer, intent(in) :: threads         !! threads of the run
    real(wp), intent(out) :: seconds       !! one step [s]
    real(wp), intent(out) :: bench_rate    !! make bench's rate [particle-steps/s]
    real(wp) :: rate1, parallel, serial
    integer :: k, t
    seconds = 0.0_wp
    bench_rate = 0.0_wp
    rate1 = 0.0_wp
    t = min(max(threads, 1), 2)
    do k = 1, size(bench_rows)
      if (basis < 1 .or. basis > size(basis_names)) exit
      if (bench_rows(k)%basis == basis_names(basis)) then
        bench_rate = bench_rows(k)%rate(t)
        rate1 = bench_rows(k)%rate(1)
      end if
    end do
    if (.not. (bench_rate > 0.0_wp .and. rate1 > 0.0_wp)) return   ! not measured (make bench)
    ! the particles at the bench's rate less its grid's share, the grid's nodes and fields,
    ! foam and F-bar run in parallel loops; the contact search and the fixed cost in one
    parallel = c%particles*(1.0_wp/rate1 - cost_node*bench_nodes) + &
               cost_node*c%nodes*real(c%fields, wp) + cost_foam*c%foam + &
               cost_foam_plane*c%foam_plane + cost_fbar*c%fbar
    serial = cost_body_entry*c%contact + &
             cost_self_entry*c%self + cost_step
    seconds = parallel*rate1/bench_rate + serial
  end subroutine cost_step_seconds

  !> The wall time of `steps` steps of a case on `threads` threads of the release build [s]
  !! (cost_step_seconds), the throughput that makes [particle-steps/s] and make bench's for the
  !! basis, and a warning line when it is beyond an hour ('' otherwise); rate = 0 where make
  !! bench has not measured the basis.
  subroutine advice_wall_time(steps, c, basis, threads, seconds, rate, bench_rate, warning)
    real(wp), intent(in) :: steps          !! steps of the run [-]
    type(cost_counts_t), intent(in) :: c   !! the case's counts
    integer, intent(in) :: basis           !! BASIS_* code
    integer, intent(in) :: threads         !! threads of the run
    real(wp), intent(out) :: seconds       !! estimated wall time [s]
    real(wp), intent(out) :: rate          !! its throughput [particle-steps/s]
    real(wp), intent(out) :: bench_rate    !! make bench's for the basis [particle-steps/s]
    character(len=:), allocatable, intent(out) :: warning  !! '' or the warning
    real(wp) :: one
    rate = 0.0_wp
    seconds = 0.0_wp
    warning = ''
    call cost_step_seconds(c, basis, threads, one, bench_rate)
    if (.not. one > 0.0_wp) return         ! not measured yet (make bench)
    seconds = steps*one
    rate = c%particles/one
    if (seconds > long_run) warning = 'the run will take about '//hms(seconds)//' (h:mm:ss). '// &
      'Set checkpoint_every = 600 (docs/output.md#checkpoints-and-restart)'
  end subroutine advice_wall_time
end module mpm_cost
