!> The LAPACK and BLAS routines cfrd calls itself, their explicit interfaces in one place
!> (OpenBLAS in the release build, Debian's liblapack / libblas in the debug build): the LU,
!> solve and condition estimate of small dense matrices (UMFPACK's row updates, the contact
!> systems' reduced matrix in cfrd_schur) and the two kernels cfrd_schur builds on.
module cfrd_lapack
    use cfrd_kinds, only: dp
    implicit none
    private

    public :: dgetrf, dgetrs, dgecon, dsyrk, dtrmv

    interface
        !> LU factorisation with partial pivoting.
        subroutine dgetrf(m, n, a, lda, ipiv, info)
            import :: dp
            integer, intent(in) :: m, n, lda
            real(dp), intent(inout) :: a(lda, *)
            integer, intent(out) :: ipiv(*), info
        end subroutine dgetrf

        !> Solve with dgetrf's factors.
        subroutine dgetrs(trans, n, nrhs, a, lda, ipiv, b, ldb, info)
            import :: dp
            character, intent(in) :: trans
            integer, intent(in) :: n, nrhs, lda, ldb, ipiv(*)
            real(dp), intent(in) :: a(lda, *)
            real(dp), intent(inout) :: b(ldb, *)
            integer, intent(out) :: info
        end subroutine dgetrs

        !> Reciprocal condition estimate from dgetrf's factors.
        subroutine dgecon(norm, n, a, lda, anorm, rcond, work, iwork, info)
            import :: dp
            character, intent(in) :: norm
            integer, intent(in) :: n, lda
            real(dp), intent(in) :: a(lda, *), anorm
            real(dp), intent(out) :: rcond, work(*)
            integer, intent(out) :: iwork(*), info
        end subroutine dgecon

        !> C = alpha A A^T + beta C (one triangle of C).
        subroutine dsyrk(uplo, trans, n, k, alpha, a, lda, beta, c, ldc)
            import :: dp
            character, intent(in) :: uplo, trans
            integer, intent(in) :: n, k, lda, ldc
            real(dp), intent(in) :: alpha, beta, a(lda, *)
            real(dp), intent(inout) :: c(ldc, *)
        end subroutine dsyrk

        !> x = A x or A^T x, A triangular.
        subroutine dtrmv(uplo, trans, diag, n, a, lda, x, incx)
            import :: dp
            character, intent(in) :: uplo, trans, diag
            integer, intent(in) :: n, lda, incx
            real(dp), intent(in) :: a(lda, *)
            real(dp), intent(inout) :: x(*)
        end subroutine dtrmv
    end interface

end module cfrd_lapack
