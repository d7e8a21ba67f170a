!> Compressed-column sparse matrices for the global stiffness: the pattern is built once per
!> mesh and set of active elements, with a map from every element matrix entry to its place
!> in the value array, so that assembly per iteration is a plain scatter-add (PSBLAS's life
!> cycle: build the pattern once, then zero and re-add values).
module cfrd_sparse
    use cfrd_kinds, only: dp
    use cfrd_error, only: error_t, fatal_error
    implicit none
    private

    public :: sparse_pattern_t, build_pattern, assemble_element, csc_matvec

    !> Pattern of a square matrix in compressed columns (0-based, as UMFPACK wants), and the
    !> element-to-value map: entry (i, j) of element e's m x m matrix (column-major) goes to
    !> values(map(map_ptr(e) + (j-1)*m + i - 1)), or nowhere when the map holds 0 (row or
    !> column is a prescribed dof).
    type :: sparse_pattern_t
        integer :: n = 0
        integer :: nnz = 0
        integer, allocatable :: colptr(:)
        integer, allocatable :: rowind(:)
        integer, allocatable :: map_ptr(:)
        integer, allocatable :: map(:)
    end type sparse_pattern_t

contains

    !> Build the pattern of a matrix of order n assembled from elements whose equation numbers
    !> are dofs(dof_ptr(e):dof_ptr(e+1)-1); entries <= 0 are not equations and are skipped.
    !> Cost is linear in the number of element entries: columns gather their elements through
    !> an inverse list, rows are de-duplicated with a marker array and each (short) column is
    !> sorted by insertion.
    subroutine build_pattern(pattern, n, dof_ptr, dofs, error)
        type(sparse_pattern_t), intent(out) :: pattern
        integer, intent(in) :: n
        integer, intent(in) :: dof_ptr(:), dofs(:)
        type(error_t), allocatable, intent(out) :: error
        integer, allocatable :: col_elem_ptr(:), col_elem(:), marker(:), fill(:)
        integer :: nelem, e, k, j, i, p, q, row, eq, m, count, pos
        character(len=40) :: text

        nelem = size(dof_ptr) - 1
        if (n < 1) then
            call fatal_error(error, 'no free degree of freedom: every dof is prescribed')
            return
        end if
        if (any(dofs > n)) then
            write (text, '(i0)') n
            call fatal_error(error, 'internal: equation number above n = '//trim(text))
            return
        end if

        ! Inverse list: the elements touching each equation.
        allocate (col_elem_ptr(n + 1), source=0)
        do k = 1, size(dofs)
            if (dofs(k) > 0) col_elem_ptr(dofs(k) + 1) = col_elem_ptr(dofs(k) + 1) + 1
        end do
        col_elem_ptr(1) = 1
        do j = 1, n
            col_elem_ptr(j + 1) = col_elem_ptr(j + 1) + col_elem_ptr(j)
        end do
        allocate (col_elem(col_elem_ptr(n + 1) - 1), fill(n))
        fill = col_elem_ptr(1:n)
        do e = 1, nelem
            do k = dof_ptr(e), dof_ptr(e + 1) - 1
                eq = dofs(k)
                if (eq <= 0) cycle
                col_elem(fill(eq)) = e
                fill(eq) = fill(eq) + 1
            end do
        end do

        ! Count, then fill, the distinct rows of each column.
        allocate (marker(n), source=0)
        allocate (pattern%colptr(n + 1))
        pattern%colptr(1) = 0
        do j = 1, n
            count = 0
            do p = col_elem_ptr(j), col_elem_ptr(j + 1) - 1
                e = col_elem(p)
                do k = dof_ptr(e), dof_ptr(e + 1) - 1
                    row = dofs(k)
                    if (row <= 0) cycle
                    if (marker(row) == j) cycle
                    marker(row) = j
                    count = count + 1
                end do
            end do
            pattern%colptr(j + 1) = pattern%colptr(j) + count
        end do
        pattern%n = n
        pattern%nnz = pattern%colptr(n + 1)
        allocate (pattern%rowind(pattern%nnz))
        marker = 0
        do j = 1, n
            pos = pattern%colptr(j)
            do p = col_elem_ptr(j), col_elem_ptr(j + 1) - 1
                e = col_elem(p)
                do k = dof_ptr(e), dof_ptr(e + 1) - 1
                    row = dofs(k)
                    if (row <= 0) cycle
                    if (marker(row) == j) cycle
                    marker(row) = j
                    pos = pos + 1
                    pattern%rowind(pos) = row - 1
                end do
            end do
            call insertion_sort(pattern%rowind(pattern%colptr(j) + 1:pattern%colptr(j + 1)))
        end do

        ! Element maps: the value position of every (row, column) pair of each element.
        allocate (pattern%map_ptr(nelem + 1))
        pattern%map_ptr(1) = 1
        do e = 1, nelem
            m = dof_ptr(e + 1) - dof_ptr(e)
            pattern%map_ptr(e + 1) = pattern%map_ptr(e) + m*m
        end do
        allocate (pattern%map(pattern%map_ptr(nelem + 1) - 1))
        do e = 1, nelem
            m = dof_ptr(e + 1) - dof_ptr(e)
            q = pattern%map_ptr(e)
            do j = 1, m
                eq = dofs(dof_ptr(e) + j - 1)
                do i = 1, m
                    row = dofs(dof_ptr(e) + i - 1)
                    if (eq > 0 .and. row > 0) then
                        pattern%map(q) = find_row(pattern, eq, row)
                    else
                        pattern%map(q) = 0
                    end if
                    q = q + 1
                end do
            end do
        end do
    end subroutine build_pattern

    !> 1-based position in rowind/values of row `row` in column `col` (both 1-based); binary
    !> search in the sorted column. The row is known to be there.
    pure integer function find_row(pattern, col, row) result(pos)
        type(sparse_pattern_t), intent(in) :: pattern
        integer, intent(in) :: col, row
        integer :: lo, hi, mid
        lo = pattern%colptr(col) + 1
        hi = pattern%colptr(col + 1)
        do while (lo < hi)
            mid = (lo + hi)/2
            if (pattern%rowind(mid) < row - 1) then
                lo = mid + 1
            else
                hi = mid
            end if
        end do
        pos = lo
    end function find_row

    pure subroutine insertion_sort(a)
        integer, intent(inout) :: a(:)
        integer :: i, j, key
        do i = 2, size(a)
            key = a(i)
            j = i - 1
            do while (j >= 1)
                if (a(j) <= key) exit
                a(j + 1) = a(j)
                j = j - 1
            end do
            a(j + 1) = key
        end do
    end subroutine insertion_sort

    !> values += element e's matrix ke, scattered through the precomputed map.
    pure subroutine assemble_element(pattern, values, e, ke)
        type(sparse_pattern_t), intent(in) :: pattern
        real(dp), intent(inout) :: values(:)
        integer, intent(in) :: e
        real(dp), intent(in) :: ke(:, :)
        integer :: i, j, m, q, pos
        m = size(ke, 1)
        q = pattern%map_ptr(e)
        do j = 1, m
            do i = 1, m
                pos = pattern%map(q)
                if (pos > 0) values(pos) = values(pos) + ke(i, j)
                q = q + 1
            end do
        end do
    end subroutine assemble_element

    !> y = A x.
    pure subroutine csc_matvec(pattern, values, x, y)
        type(sparse_pattern_t), intent(in) :: pattern
        real(dp), intent(in) :: values(:), x(:)
        real(dp), intent(out) :: y(:)
        integer :: j, p
        y(1:pattern%n) = 0.0_dp
        do j = 1, pattern%n
            do p = pattern%colptr(j) + 1, pattern%colptr(j + 1)
                y(pattern%rowind(p) + 1) = y(pattern%rowind(p) + 1) + values(p)*x(j)
            end do
        end do
    end subroutine csc_matvec
end module cfrd_sparse
