!> Radial point interpolation (RPIM; Liu & Gu 2001, the paper's refs. 14-15) of a surface
!> curve through its nodes (paper Step 3, eq. 17): x(s) = sum_i phi_i(s) x_i over the nodes
!> nearest in arc length, with multiquadric radial functions R(r) = (r^2 + (alpha_c d_c)^2)^q
!> augmented by the linear polynomial (1, s). The shape functions interpolate
!> (phi_i(s_j) = delta_ij), sum to one and reproduce linear fields, so a straight surface
!> stays straight and a uniform pressure still passes exactly (docs/theory.md section 14).
module cfrd_rpim
    use cfrd_kinds, only: dp
    implicit none
    private

    public :: rpim_shape, rpim_support, rpim_support_size

    !> Nodes in a support (fewer at a short chain).
    integer, parameter :: rpim_support_size = 4
    !> Multiquadric parameters (Liu & Gu: q = 1.03, alpha_c = 4 work well).
    real(dp), parameter :: q = 1.03_dp, alpha_c = 4.0_dp

contains

    !> The support of parameter s in a chain of nodes at parameters sn(1:n) (ascending):
    !> the indices first..first+m-1 of the m nearest nodes (m = min(n, 4)), centred on s.
    pure subroutine rpim_support(sn, s, first, m)
        real(dp), intent(in) :: sn(:), s
        integer, intent(out) :: first, m
        integer :: k, n
        n = size(sn)
        m = min(n, rpim_support_size)
        ! the segment holding s
        k = 1
        do while (k < n - 1)
            if (s < sn(k + 1)) exit
            k = k + 1
        end do
        first = max(1, min(k - (m - 2)/2, n - m + 1))
    end subroutine rpim_support

    !> Shape functions phi(1:m) at s of the support nodes at parameters sn(1:m).
    pure subroutine rpim_shape(sn, s, phi)
        real(dp), intent(in) :: sn(:), s
        real(dp), intent(out) :: phi(:)
        real(dp) :: g(size(sn) + 2, size(sn) + 2), rhs(size(sn) + 2), dc2
        integer :: m, i, j
        m = size(sn)
        if (m == 1) then
            phi = 1.0_dp
            return
        end if
        dc2 = (alpha_c*(sn(m) - sn(1))/(m - 1))**2
        g = 0.0_dp
        do j = 1, m
            do i = 1, m
                g(i, j) = radial((sn(i) - sn(j))**2)
            end do
            g(j, m + 1) = 1.0_dp
            g(j, m + 2) = sn(j)
            g(m + 1, j) = 1.0_dp
            g(m + 2, j) = sn(j)
        end do
        do i = 1, m
            rhs(i) = radial((s - sn(i))**2)
        end do
        rhs(m + 1) = 1.0_dp
        rhs(m + 2) = s
        ! G is symmetric: phi^T = [R(s)^T p(s)^T] G^-1, i.e. G [phi; lambda] = [R(s); p(s)]
        call solve(g, rhs)
        phi = rhs(1:m)
    contains
        pure real(dp) function radial(r2)
            real(dp), intent(in) :: r2
            radial = (r2 + dc2)**q
        end function radial
    end subroutine rpim_shape

    !> Gaussian elimination with partial pivoting of a small dense system, in place.
    pure subroutine solve(a, b)
        real(dp), intent(inout) :: a(:, :), b(:)
        integer :: n, k, p, i
        real(dp) :: row(size(a, 2)), t, f
        n = size(b)
        do k = 1, n
            p = k - 1 + maxloc(abs(a(k:n, k)), dim=1)
            if (p /= k) then
                row = a(k, :)
                a(k, :) = a(p, :)
                a(p, :) = row
                t = b(k)
                b(k) = b(p)
                b(p) = t
            end if
            do i = k + 1, n
                f = a(i, k)/a(k, k)
                a(i, k:n) = a(i, k:n) - f*a(k, k:n)
                b(i) = b(i) - f*b(k)
            end do
        end do
        do k = n, 1, -1
            b(k) = (b(k) - dot_product(a(k, k + 1:n), b(k + 1:n)))/a(k, k)
        end do
    end subroutine solve
end module cfrd_rpim
