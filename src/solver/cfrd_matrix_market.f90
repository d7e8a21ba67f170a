!> A measuring aid (issue 21, docs/performance.md "(k)"): with the environment variable
!> CFRD_WRITE_MATRIX=PATH set, the first matrix factorised in stage K (CFRD_WRITE_MATRIX_STAGE,
!> default 1) is written to PATH in Matrix Market coordinate format, so that other sparse
!> solvers can be timed on the very matrix cfrd factorises (tools/factor_floor.c). Off by
!> default; it reads the matrix only, so results are unchanged.
module cfrd_matrix_market
    use cfrd_kinds, only: dp
    use cfrd_sparse, only: sparse_pattern_t
    implicit none
    private

    public :: write_matrix_if_asked

contains

    !> Write pattern / values when CFRD_WRITE_MATRIX is set, `context` names stage K
    !> ('stage K (...') and `before` (the stage's factorisations so far) is 0. A file that
    !> cannot be written is reported on standard error and otherwise ignored.
    subroutine write_matrix_if_asked(pattern, values, context, before)
        type(sparse_pattern_t), intent(in) :: pattern
        real(dp), intent(in) :: values(:)
        character(len=*), intent(in) :: context
        integer, intent(in) :: before
        character(len=4096) :: path
        character(len=32) :: text
        integer :: length, status, stage, wanted, unit, j, p
        if (before /= 0) return
        call get_environment_variable('CFRD_WRITE_MATRIX', path, length, status)
        if (status /= 0 .or. length == 0) return
        if (index(context, 'stage ') /= 1) return
        read (context(7:), *, iostat=status) stage
        if (status /= 0) return
        wanted = 1
        call get_environment_variable('CFRD_WRITE_MATRIX_STAGE', text, length, status)
        if (status == 0 .and. length > 0) then
            read (text, *, iostat=status) wanted
            if (status /= 0) wanted = 1
        end if
        if (stage /= wanted) return
        open (newunit=unit, file=path(1:len_trim(path)), status='replace', action='write', &
              iostat=status)
        if (status /= 0) then
            write (0, '(a)') 'cfrd: CFRD_WRITE_MATRIX: cannot write '//trim(path)
            return
        end if
        write (unit, '(a)') '%%MatrixMarket matrix coordinate real general'
        write (unit, '(a)') '% cfrd: the first matrix factorised in '//trim(context)
        write (unit, '(i0,1x,i0,1x,i0)') pattern%n, pattern%n, pattern%colptr(pattern%n + 1)
        do j = 1, pattern%n
            do p = pattern%colptr(j) + 1, pattern%colptr(j + 1)
                write (unit, '(i0,1x,i0,1x,es24.16e3)') pattern%rowind(p) + 1, j, values(p)
            end do
        end do
        close (unit)
    end subroutine write_matrix_if_asked

end module cfrd_matrix_market
