!> The contact systems by CHOLMOD (issue 21, docs/theory.md section 6, "Contact systems"):
!> a saddle-point matrix
!>
!>     A = [ K  C ]   nu displacement equations (K symmetric positive semi-definite),
!>         [ B  E ]   nl multiplier equations (the contact rows of one active set),
!>
!> whose C, B touch only a few displacement equations, the coupled set G (the contact
!> surfaces' nodes). K is factorised by CHOLMOD with G ordered last (constrained minimum
!> degree) and its diagonal there raised by alpha, so that a body that only its contact
!> holds (K singular on G) is still factorised; the factor's last columns L_GG give K's
!> Schur complement on G exactly, S = L_GG L_GG^T - alpha I, and the reduced system
!>
!>     R = [ S  C_G ]   (ng + nl, dense)
!>         [ B_G  E ]
!>
!> is factorised by LAPACK's LU. A solve is CHOLMOD's forward half (kept for the next solve
!> of the same displacement right-hand side), R's solve, CHOLMOD's backward half. A new
!> active set (new B, E with the same K) refactorises R alone (`update`): the active-set
!> iterations cost no sparse factorisation. K's factorisation can be set aside (`keep`) and
!> is taken back when the same K comes again.
module cfrd_schur
    use cfrd_kinds, only: dp
    use cfrd_error, only: error_t, fatal_error, numerical_error
    use cfrd_sparse, only: sparse_pattern_t
    use cfrd_cholmod, only: cholmod_t
    use cfrd_umfpack, only: rcond_min, singular_text
    use cfrd_strings, only: to_text
    use cfrd_lapack, only: dgetrf, dgetrs, dsyrk, dtrmv
    implicit none
    private

    public :: schur_t, reduced_order_max

    !> The largest order of the dense reduced matrix (coupled equations plus multipliers)
    !> taken [choice, estimated]: its LU costs (2/3) m^3 flops and m^2 doubles at every new
    !> active set, 18 Gflop and 72 MB at 3000, which is about a whole sparse LU of the x8
    !> contact system (0.2-0.3 s, docs/performance.md (ab)); a system whose reduced matrix
    !> would be larger (a contact surface of some 1,000 nodes and more) goes to UMFPACK.
    integer, parameter :: reduced_order_max = 3000


    !> The numbers of one factorisation of K: its CHOLMOD factor, K's values (unshifted, to
    !> know it again), the shift, L_GG, S and the pivots of the other columns.
    type :: k_factor_t
        type(cholmod_t) :: llt
        real(dp), allocatable :: kbase(:)
        real(dp), allocatable :: g(:, :), s(:, :)
        real(dp) :: alpha = 0.0_dp
        real(dp) :: pivots(2) = 0.0_dp
        logical :: factorised = .false.
    end type k_factor_t

    !> A saddle-point pattern analysed for the Schur path, and its current factorisation.
    type :: schur_t
        private
        integer :: nu = 0, nl = 0, ng = 0
        type(sparse_pattern_t) :: kpattern    !! K's pattern (the leading nu x nu block)
        integer, allocatable :: k_from(:)     !! each K entry's position in A's pattern
        integer, allocatable :: shift_at(:)   !! K entries on G's diagonal
        integer, allocatable :: r_from(:), r_to(:)   !! A's entries of R, their place in R
        logical, allocatable :: last(:)       !! G: the equations CHOLMOD orders last
        integer, allocatable :: g_eq(:)       !! G's equations in the factor's order
        logical :: analysed = .false.
        type(k_factor_t) :: k, spare
        real(dp), allocatable :: lu(:)        !! R's LU (ng + nl)^2, column-major
        integer, allocatable :: ipiv(:)
        real(dp) :: u_range(2) = 0.0_dp       !! smallest and largest |U_ii| of R
        !> The last forward half and its right-hand side: the active-set iterations of one
        !> solve change the multipliers' right-hand side only (cfrd_active_set)
        real(dp), allocatable :: b_last(:), z_last(:)
        !> A partial solve's right-hand side of the backward half, until `complete`
        real(dp), allocatable :: z_part(:)
        logical :: factorised = .false.
    contains
        procedure :: analyse
        procedure :: is_analysed
        procedure :: factorise
        procedure :: update
        procedure :: same_k
        procedure :: solve
        procedure :: complete
        procedure :: rcond
        procedure :: factor_nonzeros
        procedure :: keep
        procedure :: take_analysis
        procedure :: release
    end type schur_t

contains

    !> The pattern of A (its last nl equations the multipliers): K's pattern, the coupled
    !> set G, and CHOLMOD's analysis of K with G last. `fits` is false, and nothing is
    !> analysed, when the reduced matrix would be above reduced_order_max.
    subroutine analyse(self, pattern, nl, error, fits)
        class(schur_t), intent(inout) :: self
        type(sparse_pattern_t), intent(in) :: pattern
        integer, intent(in) :: nl
        type(error_t), allocatable, intent(out) :: error
        logical, intent(out) :: fits
        logical, allocatable :: coupled(:)
        integer, allocatable :: perm(:), place(:), rows(:), cols(:)
        integer :: i, j, p, k, nu, m, ri, cj
        call self%release()
        fits = .false.
        nu = pattern%n - nl
        if (nu < 1 .or. nl < 0) then
            call fatal_error(error, 'internal: a saddle-point system without displacements', &
                             numerical_error)
            return
        end if
        self%nu = nu
        self%nl = nl
        allocate (coupled(nu), source=.false.)
        allocate (rows(pattern%nnz), cols(pattern%nnz))
        do j = 1, pattern%n
            do p = pattern%colptr(j) + 1, pattern%colptr(j + 1)
                i = pattern%rowind(p) + 1
                rows(p) = i
                cols(p) = j
                if (j <= nu .and. i > nu) coupled(j) = .true.
                if (j > nu .and. i <= nu) coupled(i) = .true.
            end do
        end do
        self%ng = count(coupled)
        fits = self%ng + nl <= reduced_order_max
        if (.not. fits) then
            call self%release()
            return
        end if
        ! K's pattern: the entries of A's leading block, in A's order
        self%k_from = pack([(p, p=1, pattern%nnz)], rows <= nu .and. cols <= nu)
        self%kpattern%n = nu
        self%kpattern%nnz = size(self%k_from)
        self%kpattern%rowind = pattern%rowind(self%k_from)
        allocate (self%kpattern%colptr(nu + 1))
        self%kpattern%colptr(1) = 0
        do j = 1, nu
            p = pattern%colptr(j)
            self%kpattern%colptr(j + 1) = self%kpattern%colptr(j) + &
                                          count(rows(p + 1:pattern%colptr(j + 1)) <= nu)
        end do
        self%shift_at = pack([(k, k=1, size(self%k_from))], &
                             rows(self%k_from) == cols(self%k_from) .and. &
                             coupled(min(rows(self%k_from), nu)))
        self%last = coupled
        call self%k%llt%analyse(self%kpattern, error, last=coupled)
        if (allocated(error)) return
        call self%k%llt%permutation(perm, error)
        if (allocated(error)) return
        ! G's equations in the factor's order: place(i) = 1 .. ng
        allocate (place(nu), source=0)
        do k = nu - self%ng + 1, nu
            place(perm(k)) = k - (nu - self%ng)
        end do
        self%g_eq = perm(nu - self%ng + 1:nu)
        if (count(place > 0 .and. coupled) /= self%ng) then
            call fatal_error(error, 'internal: CHOLMOD did not order the coupled equations last', &
                             numerical_error)
            return
        end if
        ! the entries of R: C, B and E
        m = self%ng + nl
        self%r_from = pack([(p, p=1, pattern%nnz)], rows > nu .or. cols > nu)
        allocate (self%r_to(size(self%r_from)))
        do k = 1, size(self%r_from)
            p = self%r_from(k)
            ri = merge(place(min(rows(p), nu)), self%ng + rows(p) - nu, rows(p) <= nu)
            cj = merge(place(min(cols(p), nu)), self%ng + cols(p) - nu, cols(p) <= nu)
            self%r_to(k) = (cj - 1)*m + ri
        end do
        self%analysed = .true.
    end subroutine analyse

    logical function is_analysed(self)
        class(schur_t), intent(in) :: self
        is_analysed = self%analysed
    end function is_analysed

    !> Factorise A: K by CHOLMOD (`reused` when it is the K factorised already, or the one
    !> set aside by keep, taken back), then R. `positive` is false, and nothing is kept,
    !> when CHOLMOD finds K (with G's shift) not positive definite: the caller factorises A
    !> by UMFPACK. A singular R is an error, as UMFPACK's singular matrix is.
    subroutine factorise(self, pattern, values, positive, error, reused)
        class(schur_t), intent(inout) :: self
        type(sparse_pattern_t), intent(in) :: pattern
        real(dp), intent(in) :: values(:)
        logical, intent(out) :: positive
        type(error_t), allocatable, intent(out) :: error
        logical, intent(out) :: reused
        real(dp), allocatable :: kvalues(:)
        logical :: current
        positive = .false.
        reused = .false.
        self%factorised = .false.
        if (.not. self%analysed) then
            call fatal_error(error, 'internal: Schur factorisation without an analysis', &
                             numerical_error)
            return
        end if
        if (pattern%n /= self%nu + self%nl .or. size(values) < pattern%nnz) then
            call fatal_error(error, 'internal: Schur factorisation given another pattern', &
                             numerical_error)
            return
        end if
        kvalues = values(self%k_from)
        ! the K factorised already (new contact rows only: a regularised retry), or the K
        ! set aside: R alone
        current = .false.
        if (self%k%factorised) current = all(kvalues == self%k%kbase)
        if (self%spare%factorised .and. .not. current) reused = all(kvalues == self%spare%kbase)
        if (reused) then
            call exchange_factors(self%k, self%spare)
            self%spare%factorised = .false.
        else if (.not. current) then
            if (.not. self%k%llt%is_analysed()) call self%k%llt%copy_analysis(self%spare%llt)
            if (.not. self%k%llt%is_analysed()) then
                call self%k%llt%analyse(self%kpattern, error, last=self%last)
                if (allocated(error)) return
            end if
            self%k%factorised = .false.
            self%k%kbase = kvalues
            self%k%alpha = 0.0_dp
            if (size(self%shift_at) > 0) self%k%alpha = maxval(kvalues(self%shift_at))
            kvalues(self%shift_at) = kvalues(self%shift_at) + self%k%alpha
            call self%k%llt%factorise(self%kpattern, kvalues, positive, error)
            if (allocated(error) .or. .not. positive) return
            if (allocated(self%k%g)) deallocate (self%k%g, self%k%s)
            allocate (self%k%g(self%ng, self%ng), self%k%s(self%ng, self%ng))
            call self%k%llt%tail(self%ng, self%k%g, self%k%pivots, error)
            if (allocated(error)) return
            call complement(self%k)
            self%k%factorised = .true.
        end if
        positive = .true.
        reused = reused .or. current
        if (allocated(self%b_last) .and. .not. current) deallocate (self%b_last, self%z_last)
        call self%update(values, error)
    end subroutine factorise

    !> S = L_GG L_GG^T - alpha I (both triangles).
    subroutine complement(k)
        type(k_factor_t), intent(inout) :: k
        integer :: i, ng
        ng = size(k%g, 1)
        if (ng == 0) return
        call dsyrk('L', 'N', ng, ng, 1.0_dp, k%g, ng, 0.0_dp, k%s, ng)
        do i = 1, ng
            k%s(i, i) = k%s(i, i) - k%alpha
            k%s(i, i + 1:) = k%s(i + 1:, i)
        end do
    end subroutine complement

    !> R of `values` (a new active set: the same K, new contact rows) and its LU. A
    !> singular or nearly singular R (rcond below rcond_min) is an error.
    subroutine update(self, values, error)
        class(schur_t), intent(inout) :: self
        real(dp), intent(in) :: values(:)
        type(error_t), allocatable, intent(out) :: error
        integer :: m, i, info
        real(dp) :: u
        self%factorised = .false.
        if (allocated(self%z_part)) deallocate (self%z_part)
        if (.not. self%k%factorised) then
            call fatal_error(error, 'internal: Schur update without a factorisation of K', &
                             numerical_error)
            return
        end if
        m = self%ng + self%nl
        if (allocated(self%lu)) then
            if (size(self%lu) /= m*m) deallocate (self%lu, self%ipiv)
        end if
        if (.not. allocated(self%lu)) allocate (self%lu(m*m), self%ipiv(max(m, 1)))
        self%lu = 0.0_dp
        do i = 1, self%ng
            self%lu((i - 1)*m + 1:(i - 1)*m + self%ng) = self%k%s(:, i)
        end do
        do i = 1, size(self%r_from)
            self%lu(self%r_to(i)) = self%lu(self%r_to(i)) + values(self%r_from(i))
        end do
        info = 0
        if (m > 0) call dgetrf(m, m, self%lu, m, self%ipiv, info)
        self%u_range = [huge(1.0_dp), 0.0_dp]
        do i = 1, m
            u = abs(self%lu((i - 1)*m + i))
            self%u_range = [min(self%u_range(1), u), max(self%u_range(2), u)]
        end do
        if (info /= 0 .or. .not. (self%rcond() >= rcond_min)) then
            call fatal_error(error, singular_text('the contact system''s reduced matrix '// &
                                                  '(order '//to_text(m)//')', self%rcond()), &
                             numerical_error)
            return
        end if
        self%factorised = .true.
    end subroutine update

    !> Whether `values` has the K of the current factorisation, bit for bit.
    logical function same_k(self, values)
        class(schur_t), intent(in) :: self
        real(dp), intent(in) :: values(:)
        same_k = .false.
        if (.not. self%k%factorised) return
        same_k = all(values(self%k_from) == self%k%kbase)
    end function same_k

    !> x = A^-1 b. G's displacements are those of R's solve (the backward half gives them
    !> again to round-off only). `partial`: the multipliers and G's displacements alone, the
    !> others zero until `complete` (what an active-set iteration reads: the contact
    !> surfaces' motion and tractions; docs/theory.md section 6).
    subroutine solve(self, b, x, error, partial)
        class(schur_t), intent(inout) :: self
        real(dp), intent(in) :: b(:)
        real(dp), intent(out) :: x(:)
        type(error_t), allocatable, intent(out) :: error
        logical, intent(in), optional :: partial
        real(dp), allocatable :: z(:), y(:)
        integer :: nu, ng, n0, m, info
        if (.not. self%factorised) then
            call fatal_error(error, 'internal: Schur solve without a factorisation', &
                             numerical_error)
            return
        end if
        nu = self%nu
        ng = self%ng
        n0 = nu - ng
        m = ng + self%nl
        allocate (y(m))
        if (allocated(self%b_last)) then
            if (.not. all(b(1:nu) == self%b_last)) deallocate (self%b_last, self%z_last)
        end if
        if (.not. allocated(self%b_last)) then
            allocate (self%z_last(nu))
            call self%k%llt%forward(b(1:nu), self%z_last, error)
            if (allocated(error)) then
                deallocate (self%z_last)
                return
            end if
            self%b_last = b(1:nu)
        end if
        z = self%z_last
        ! the right-hand side of G's equations after the others' elimination: L_GG z_G
        y(1:ng) = z(n0 + 1:nu)
        if (ng > 0) call dtrmv('L', 'N', 'N', ng, self%k%g, ng, y, 1)
        y(ng + 1:m) = b(nu + 1:nu + self%nl)
        if (m > 0) call dgetrs('N', m, 1, self%lu, m, self%ipiv, y, m, info)
        ! G's displacements back into the factor's order: z_G = L_GG^T du_G
        z(n0 + 1:nu) = y(1:ng)
        if (ng > 0) call dtrmv('L', 'T', 'N', ng, self%k%g, ng, z(n0 + 1:nu), 1)
        x(nu + 1:nu + self%nl) = y(ng + 1:m)
        if (allocated(self%z_part)) deallocate (self%z_part)
        if (present(partial)) then
            if (partial) then
                x(1:nu) = 0.0_dp
                x(self%g_eq) = y(1:ng)
                call move_alloc(z, self%z_part)
                return
            end if
        end if
        call self%k%llt%backward(z, x(1:nu), error)
        if (allocated(error)) return
        x(self%g_eq) = y(1:ng)
    end subroutine solve

    !> The displacements a partial solve left out (the backward half of that solve), into
    !> x as the partial solve returned it; nothing when the last solve was whole.
    subroutine complete(self, x, error)
        class(schur_t), intent(inout) :: self
        real(dp), intent(inout) :: x(:)
        type(error_t), allocatable, intent(out) :: error
        real(dp), allocatable :: xg(:)
        if (.not. allocated(self%z_part)) return
        xg = x(self%g_eq)
        call self%k%llt%backward(self%z_part, x(1:self%nu), error)
        deallocate (self%z_part)
        if (allocated(error)) return
        x(self%g_eq) = xg
    end subroutine complete

    !> The reciprocal condition estimate: the smallest over the largest pivot, of K's
    !> columns before G (L_jj^2) and of R (|U_ii|); 0 before a factorisation.
    real(dp) function rcond(self)
        class(schur_t), intent(in) :: self
        real(dp) :: lo, hi
        rcond = 0.0_dp
        if (.not. self%k%factorised) return
        lo = self%u_range(1)
        hi = self%u_range(2)
        if (self%nu > self%ng) then
            lo = min(lo, self%k%pivots(1))
            hi = max(hi, self%k%pivots(2))
        end if
        if (hi > 0.0_dp) rcond = lo/hi
    end function rcond

    !> Nonzeros of the factors: CHOLMOD's L and R's LU.
    integer function factor_nonzeros(self)
        class(schur_t), intent(in) :: self
        factor_nonzeros = self%k%llt%factor_nonzeros() + (self%ng + self%nl)**2
    end function factor_nonzeros

    !> Set K's factorisation aside: factorise takes it back when it is given the same K.
    subroutine keep(self)
        class(schur_t), intent(inout) :: self
        if (.not. self%k%factorised) return
        call exchange_factors(self%k, self%spare)
        self%k%factorised = .false.
        self%factorised = .false.
        if (allocated(self%b_last)) deallocate (self%b_last, self%z_last)
        if (allocated(self%z_part)) deallocate (self%z_part)
    end subroutine keep

    !> Exchange two factorisations of K (their CHOLMOD objects too), freeing neither.
    subroutine exchange_factors(a, b)
        type(k_factor_t), intent(inout) :: a, b
        type(k_factor_t) :: swap
        real(dp) :: numbers(3)
        logical :: flag
        call a%llt%exchange(b%llt)
        call move_alloc(a%kbase, swap%kbase)
        call move_alloc(b%kbase, a%kbase)
        call move_alloc(swap%kbase, b%kbase)
        call move_alloc(a%g, swap%g)
        call move_alloc(b%g, a%g)
        call move_alloc(swap%g, b%g)
        call move_alloc(a%s, swap%s)
        call move_alloc(b%s, a%s)
        call move_alloc(swap%s, b%s)
        numbers = [a%alpha, a%pivots]
        flag = a%factorised
        a%alpha = b%alpha
        a%pivots = b%pivots
        a%factorised = b%factorised
        b%alpha = numbers(1)
        b%pivots = numbers(2:3)
        b%factorised = flag
    end subroutine exchange_factors

    !> The analysis of `from` moved into self (released first); `from` is left without one
    !> (a pattern analysed ahead, cfrd_linear_solver's adopt).
    subroutine take_analysis(self, from)
        class(schur_t), intent(inout) :: self
        type(schur_t), intent(inout) :: from
        call self%release()
        if (.not. from%analysed) return
        self%nu = from%nu
        self%nl = from%nl
        self%ng = from%ng
        self%kpattern%n = from%kpattern%n
        self%kpattern%nnz = from%kpattern%nnz
        call move_alloc(from%kpattern%colptr, self%kpattern%colptr)
        call move_alloc(from%kpattern%rowind, self%kpattern%rowind)
        call move_alloc(from%k_from, self%k_from)
        call move_alloc(from%shift_at, self%shift_at)
        call move_alloc(from%r_from, self%r_from)
        call move_alloc(from%r_to, self%r_to)
        call move_alloc(from%last, self%last)
        call move_alloc(from%g_eq, self%g_eq)
        call exchange_factors(self%k, from%k)
        self%analysed = .true.
        call from%release()
    end subroutine take_analysis

    !> Free everything (a new pattern follows).
    subroutine release(self)
        class(schur_t), intent(inout) :: self
        call release_factor(self%k)
        call release_factor(self%spare)
        if (allocated(self%k_from)) deallocate (self%k_from)
        if (allocated(self%shift_at)) deallocate (self%shift_at)
        if (allocated(self%last)) deallocate (self%last)
        if (allocated(self%g_eq)) deallocate (self%g_eq)
        if (allocated(self%z_part)) deallocate (self%z_part)
        if (allocated(self%r_from)) deallocate (self%r_from, self%r_to)
        if (allocated(self%lu)) deallocate (self%lu, self%ipiv)
        if (allocated(self%b_last)) deallocate (self%b_last, self%z_last)
        if (allocated(self%kpattern%colptr)) deallocate (self%kpattern%colptr)
        if (allocated(self%kpattern%rowind)) deallocate (self%kpattern%rowind)
        self%nu = 0
        self%nl = 0
        self%ng = 0
        self%analysed = .false.
        self%factorised = .false.
    end subroutine release

    subroutine release_factor(k)
        type(k_factor_t), intent(inout) :: k
        call k%llt%release()
        if (allocated(k%kbase)) deallocate (k%kbase)
        if (allocated(k%g)) deallocate (k%g, k%s)
        k%factorised = .false.
    end subroutine release_factor

end module cfrd_schur
