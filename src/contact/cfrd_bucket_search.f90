!> A uniform bucket grid over segment bounding boxes: built in time linear in the number of
!> segments, and queried with a box, so that the contact search costs about the number of
!> surface segments instead of their product (issue 7: "a bucket or tree search").
module cfrd_bucket_search
    use cfrd_kinds, only: dp
    implicit none
    private

    public :: bucket_grid_t, build_grid, query_grid

    type :: bucket_grid_t
        real(dp) :: origin(2) = 0.0_dp
        real(dp) :: cell = 1.0_dp
        integer :: nx = 0, ny = 0
        integer, allocatable :: ptr(:)     !! (nx*ny + 1) start of each cell's items
        integer, allocatable :: items(:)   !! segment numbers, cell by cell
    end type bucket_grid_t

    !> At most this many cells along a side: a few stray long segments must not make the
    !> grid huge.
    integer, parameter :: max_cells = 4096

contains

    !> The grid of the boxes (xmin, ymin, xmax, ymax) of n segments, cells about `cell` wide.
    pure subroutine build_grid(grid, boxes, cell)
        type(bucket_grid_t), intent(out) :: grid
        real(dp), intent(in) :: boxes(:, :), cell
        integer :: n, k, i, j, i0, i1, j0, j1, pass
        integer, allocatable :: fill(:)
        real(dp) :: span(2)
        n = size(boxes, 2)
        if (n == 0) then
            allocate (grid%ptr(1), source=1)
            allocate (grid%items(0))
            return
        end if
        grid%origin = [minval(boxes(1, :)), minval(boxes(2, :))]
        span = [maxval(boxes(3, :)), maxval(boxes(4, :))] - grid%origin
        grid%cell = max(cell, maxval(span)/max_cells, tiny(1.0_dp))
        grid%nx = max(1, ceiling(span(1)/grid%cell))
        grid%ny = max(1, ceiling(span(2)/grid%cell))
        allocate (grid%ptr(grid%nx*grid%ny + 1), source=0)
        allocate (fill(grid%nx*grid%ny))
        ! Two passes: count the items per cell, then place them.
        do pass = 1, 2
            if (pass == 2) then
                grid%ptr(1) = 1
                do k = 1, grid%nx*grid%ny
                    grid%ptr(k + 1) = grid%ptr(k + 1) + grid%ptr(k)
                end do
                allocate (grid%items(grid%ptr(grid%nx*grid%ny + 1) - 1))
                fill = grid%ptr(1:grid%nx*grid%ny)
            end if
            do k = 1, n
                call cell_range(grid, boxes(:, k), i0, i1, j0, j1)
                do j = j0, j1
                    do i = i0, i1
                        if (pass == 1) then
                            grid%ptr(cell_index(grid, i, j) + 1) = &
                                grid%ptr(cell_index(grid, i, j) + 1) + 1
                        else
                            grid%items(fill(cell_index(grid, i, j))) = k
                            fill(cell_index(grid, i, j)) = fill(cell_index(grid, i, j)) + 1
                        end if
                    end do
                end do
            end do
        end do
    end subroutine build_grid

    !> The segments whose cells the box (xmin, ymin, xmax, ymax) touches, each once:
    !> found(1:nfound). `marker` (one entry per segment, kept by the caller between
    !> queries) and a query number `stamp` that grows from query to query de-duplicate.
    pure subroutine query_grid(grid, box, stamp, marker, found, nfound)
        type(bucket_grid_t), intent(in) :: grid
        real(dp), intent(in) :: box(4)
        integer, intent(in) :: stamp
        integer, intent(inout) :: marker(:)
        integer, intent(inout) :: found(:)
        integer, intent(out) :: nfound
        integer :: i, j, p, k, i0, i1, j0, j1
        nfound = 0
        if (grid%nx == 0) return
        call cell_range(grid, box, i0, i1, j0, j1)
        do j = j0, j1
            do i = i0, i1
                do p = grid%ptr(cell_index(grid, i, j)), grid%ptr(cell_index(grid, i, j) + 1) - 1
                    k = grid%items(p)
                    if (marker(k) == stamp) cycle
                    marker(k) = stamp
                    nfound = nfound + 1
                    found(nfound) = k
                end do
            end do
        end do
    end subroutine query_grid

    pure integer function cell_index(grid, i, j)
        type(bucket_grid_t), intent(in) :: grid
        integer, intent(in) :: i, j
        cell_index = (j - 1)*grid%nx + i
    end function cell_index

    !> Cells (clipped to the grid) that a box touches.
    pure subroutine cell_range(grid, box, i0, i1, j0, j1)
        type(bucket_grid_t), intent(in) :: grid
        real(dp), intent(in) :: box(4)
        integer, intent(out) :: i0, i1, j0, j1
        i0 = clip(floor((box(1) - grid%origin(1))/grid%cell) + 1, grid%nx)
        i1 = clip(floor((box(3) - grid%origin(1))/grid%cell) + 1, grid%nx)
        j0 = clip(floor((box(2) - grid%origin(2))/grid%cell) + 1, grid%ny)
        j1 = clip(floor((box(4) - grid%origin(2))/grid%cell) + 1, grid%ny)
    contains
        pure integer function clip(k, n)
            integer, intent(in) :: k, n
            clip = min(max(k, 1), n)
        end function clip
    end subroutine cell_range
end module cfrd_bucket_search
