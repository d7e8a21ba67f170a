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
    !> Elements may have different numbers of dofs. Cost is linear in the number of element
    !> matrix entries, with no search in long lists: one pass over the columns, each gathering
    !> its elements through an inverse list, de-duplicating rows with a marker array, sorting
    !> its (short) row list, and writing the element maps through a row-to-position array.
    subroutine build_pattern(pattern, n, dof_ptr, dofs, error)
        type(sparse_pattern_t), intent(out) :: pattern
        integer, intent(in) :: n
        integer, intent(in) :: dof_ptr(:), dofs(:)
        type(error_t), allocatable, intent(out) :: error
        integer, allocatable :: col_elem_ptr(:), col_elem(:), fill(:), rows(:)
        integer, allocatable :: marker(:), position(:)
        integer :: nelem, e, k, kl, i, p, q, row, eq, m, first, last, pos, bound
        character(len=80) :: text

        nelem = size(dof_ptr) - 1
        if (n < 1) then
            call fatal_error(error, 'no free degree of freedom: every dof is prescribed')
            return
        end if
        if (nelem < 0) then
            call fatal_error(error, 'internal: dof_ptr is empty (it needs nelem + 1 entries)')
            return
        end if
        if (nelem > 0) then
            if (dof_ptr(1) /= 1 .or. any(dof_ptr(2:) < dof_ptr(:nelem)) .or. &
                dof_ptr(nelem + 1) - 1 > size(dofs)) then
                call fatal_error(error, 'internal: dof_ptr is not a list of offsets into dofs')
                return
            end if
        end if
        if (any(dofs > n)) then
            write (text, '(a,i0,a,i0)') 'internal: equation number ', maxval(dofs), &
                ' above n = ', n
            call fatal_error(error, trim(text))
            return
        end if

        ! Inverse list: the elements touching each equation, and an upper bound on the
        ! stored entries (every column's elements' rows, counted with repetition).
        allocate (col_elem_ptr(n + 1), source=0)
        bound = 0
        do e = 1, nelem
            m = dof_ptr(e + 1) - dof_ptr(e)
            do k = dof_ptr(e), dof_ptr(e + 1) - 1
                if (dofs(k) <= 0) cycle
                col_elem_ptr(dofs(k) + 1) = col_elem_ptr(dofs(k) + 1) + 1
                bound = bound + m
            end do
        end do
        col_elem_ptr(1) = 1
        do i = 1, n
            col_elem_ptr(i + 1) = col_elem_ptr(i + 1) + col_elem_ptr(i)
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
        deallocate (fill)

        allocate (pattern%map_ptr(nelem + 1))
        pattern%map_ptr(1) = 1
        do e = 1, nelem
            m = dof_ptr(e + 1) - dof_ptr(e)
            pattern%map_ptr(e + 1) = pattern%map_ptr(e) + m*m
        end do
        ! Entries in a prescribed column are never visited below and stay 0.
        allocate (pattern%map(pattern%map_ptr(nelem + 1) - 1), source=0)

        ! Rows of column eq go to rows(first:last) at the running end, so the list stays
        ! compact; position(row) is then where that row sits, for the element maps.
        allocate (rows(bound), marker(n), position(n), pattern%colptr(n + 1))
        marker = 0
        pattern%colptr(1) = 0
        last = 0
        do eq = 1, n
            first = last + 1
            do p = col_elem_ptr(eq), col_elem_ptr(eq + 1) - 1
                e = col_elem(p)
                do k = dof_ptr(e), dof_ptr(e + 1) - 1
                    row = dofs(k)
                    if (row <= 0) cycle
                    if (marker(row) == eq) cycle
                    marker(row) = eq
                    last = last + 1
                    rows(last) = row
                end do
            end do
            call insertion_sort(rows(first:last))
            do pos = first, last
                position(rows(pos)) = pos
            end do
            pattern%colptr(eq + 1) = last
            do p = col_elem_ptr(eq), col_elem_ptr(eq + 1) - 1
                e = col_elem(p)
                m = dof_ptr(e + 1) - dof_ptr(e)
                ! Every local column of e that is equation eq (normally exactly one).
                do kl = 1, m
                    if (dofs(dof_ptr(e) + kl - 1) /= eq) cycle
                    q = pattern%map_ptr(e) + (kl - 1)*m - 1
                    do i = 1, m
                        row = dofs(dof_ptr(e) + i - 1)
                        if (row > 0) pattern%map(q + i) = position(row)
                    end do
                end do
            end do
        end do
        pattern%n = n
        pattern%nnz = last
        allocate (pattern%rowind(last))
        pattern%rowind = rows(1:last) - 1
    end subroutine build_pattern

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
