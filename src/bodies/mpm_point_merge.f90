!> Coincident points of a mesh merged into one: the corners that neighbouring quadrilaterals
!! share. O(n log n): the points sorted by x, each run of x within tol sorted by y.
module mpm_point_merge
  use mpm_kinds, only: wp
  implicit none
  private

  public :: merge_points

contains

  !> Merge points closer than tol (in both coordinates): unique points xu and the id of each
  !! input point. The unique points are numbered in the order of x (stable), each at its first
  !! point in that order. Points of different clusters are taken to lie much more than tol apart.
  pure subroutine merge_points(pts, tol, xu, ids)
    real(wp), intent(in) :: pts(:,:)             !! points [m]
    real(wp), intent(in) :: tol                  !! merge distance [m]
    real(wp), allocatable, intent(out) :: xu(:,:)  !! unique points [m]
    integer, allocatable, intent(out) :: ids(:)  !! each point's unique point [-]
    integer, allocatable :: ord(:), oy(:), lab(:), cl_id(:)
    integer :: n, a, g0, g1, i, p, q, ncl, nu
    n = size(pts, 2)
    allocate(ids(n), xu(2, n), lab(n))
    ord = sort_index(pts(1, :))
    ncl = 0
    g0 = 1
    do while (g0 <= n)                           ! runs g0..g1 of x within tol (chained)
      g1 = g0
      do while (g1 < n)
        if (pts(1, ord(g1 + 1)) - pts(1, ord(g1)) > tol) exit
        g1 = g1 + 1
      end do
      oy = sort_index(pts(2, ord(g0:g1)))        ! the run by y: a cluster is a chain within tol
      ncl = ncl + 1
      lab(g0 + oy(1) - 1) = ncl
      do i = 2, size(oy)
        p = ord(g0 + oy(i - 1) - 1)
        q = ord(g0 + oy(i) - 1)
        if (pts(2, q) - pts(2, p) > tol .or. abs(pts(1, q) - pts(1, p)) > tol) ncl = ncl + 1
        lab(g0 + oy(i) - 1) = ncl
      end do
      g0 = g1 + 1
    end do
    allocate(cl_id(ncl), source=0)
    nu = 0
    do a = 1, n                                  ! numbered at each cluster's first point in x
      if (cl_id(lab(a)) == 0) then
        nu = nu + 1
        xu(:, nu) = pts(:, ord(a))
        cl_id(lab(a)) = nu
      end if
      ids(ord(a)) = cl_id(lab(a))
    end do
    xu = xu(:, 1:nu)
  end subroutine merge_points

  !> The permutation that sorts x ascending (merge sort; stable).
  pure function sort_index(x) result(ord)
    real(wp), intent(in) :: x(:)                 !! keys [-]
    integer, allocatable :: ord(:)
    integer, allocatable :: tmp(:)
    integer :: n, w, lo, mid, hi, i, j, k
    n = size(x)
    allocate(tmp(n))
    ord = [(i, i = 1, n)]
    w = 1
    do while (w < n)
      lo = 1
      do while (lo <= n)
        mid = min(lo + w - 1, n)
        hi = min(lo + 2*w - 1, n)
        i = lo
        j = mid + 1
        k = lo
        do while (k <= hi)
          if (j > hi) then
            tmp(k) = ord(i); i = i + 1
          else if (i > mid) then
            tmp(k) = ord(j); j = j + 1
          else if (x(ord(j)) < x(ord(i))) then
            tmp(k) = ord(j); j = j + 1
          else
            tmp(k) = ord(i); i = i + 1
          end if
          k = k + 1
        end do
        lo = lo + 2*w
      end do
      ord = tmp
      w = 2*w
    end do
  end function sort_index
end module mpm_point_merge
