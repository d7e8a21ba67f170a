!> Unit tests of the pure rockfill creep law (docs/theory.md section 15) against its
!> formulas worked by hand: the final strains, the closed-form strain-time curve at constant
!> stress, the Prandtl-Reuss split of the strain increment, and irreversibility.
module test_materials_creep
    use cfrd_kinds, only: dp
    use cfrd_error, only: error_t
    use cfrd_testing, only: unittest_t, new_unittest, check
    use cfrd_rockfill_creep, only: creep_params_t, creep_final_strains, creep_advance, &
                                   creep_strain_increment
    implicit none
    private

    public :: collect_materials_creep

    real(dp), parameter :: pa = 101.325_dp

contains

    subroutine collect_materials_creep(tests)
        type(unittest_t), allocatable, intent(out) :: tests(:)
        tests = [ &
                new_unittest('final_strains_by_hand', test_final), &
                new_unittest('constant_stress_closed_form', test_closed_form), &
                new_unittest('prandtl_reuss_split', test_split), &
                new_unittest('no_recovery', test_no_recovery) &
                ]
    end subroutine collect_materials_creep

    pure function params() result(p)
        type(creep_params_t) :: p
        p = creep_params_t(alpha=0.01_dp, b=0.002_dp, mc=0.5_dp, d=0.004_dp, l=1.0_dp, &
                           pa=pa, sigma3_floor=0.1_dp*pa)
    end function params

    !> eps_vf = b (sigma3/pa)^mc: 0.002 * 4^0.5 = 0.004 at sigma3 = 4 pa;
    !> eps_sf = d (S/(1-S))^l: 0.004 * 1 at S = 0.5, 0.004 * 3 at S = 0.75; 0 at S = 0.
    subroutine test_final(error)
        type(error_t), allocatable, intent(out) :: error
        real(dp) :: ev, es
        call creep_final_strains(params(), 4.0_dp*pa, 0.5_dp, ev, es)
        call check(error, ev, 0.004_dp, 'eps_vf at 4 pa', rel=1e-14_dp)
        if (allocated(error)) return
        call check(error, es, 0.004_dp, 'eps_sf at S = 0.5', rel=1e-14_dp)
        if (allocated(error)) return
        call creep_final_strains(params(), 4.0_dp*pa, 0.75_dp, ev, es)
        call check(error, es, 0.012_dp, 'eps_sf at S = 0.75', rel=1e-14_dp)
        if (allocated(error)) return
        call creep_final_strains(params(), 0.0_dp, 0.0_dp, ev, es)
        call check(error, ev, 0.002_dp*sqrt(0.1_dp), 'eps_vf at the sigma3 floor', &
                   rel=1e-14_dp)
        if (allocated(error)) return
        call check(error, es, 0.0_dp, 'eps_sf at S = 0', abs=0.0_dp)
    end subroutine test_final

    !> At constant stress, steps of any size land on eps_f (1 - exp(-alpha t)): seven
    !> unequal steps to t = 400 days against the closed form, 1e-12 relative.
    subroutine test_closed_form(error)
        type(error_t), allocatable, intent(out) :: error
        real(dp), parameter :: steps(7) = [0.5_dp, 3.0_dp, 20.0_dp, 76.5_dp, 100.0_dp, &
                                           0.0_dp, 200.0_dp]
        real(dp) :: ev, es, t, de(4), stress(4)
        integer :: i
        stress = [-300.0_dp, -700.0_dp, -400.0_dp, 50.0_dp]
        ev = 0.0_dp
        es = 0.0_dp
        t = 0.0_dp
        do i = 1, size(steps)
            call creep_strain_increment(params(), stress, 4.0_dp*pa, 0.5_dp, steps(i), &
                                        ev, es, de)
            t = t + steps(i)
            call check(error, ev, 0.004_dp*(1.0_dp - exp(-0.01_dp*t)), 'eps_v(t)', &
                       rel=1e-12_dp)
            if (allocated(error)) return
            call check(error, es, 0.004_dp*(1.0_dp - exp(-0.01_dp*t)), 'eps_s(t)', &
                       rel=1e-12_dp)
            if (allocated(error)) return
        end do
    end subroutine test_closed_form

    !> The increment's trace is -d eps_v (compaction, tension positive); its deviatoric part
    !> has generalised shear strain sqrt(2/3 e:e) = d eps_s and is parallel to the stress
    !> deviator (major compression shortens).
    subroutine test_split(error)
        type(error_t), allocatable, intent(out) :: error
        real(dp) :: ev, es, de(4), stress(4), mean, e(4), s(4), dev, des
        stress = [-300.0_dp, -700.0_dp, -400.0_dp, 50.0_dp]
        ev = 0.0_dp
        es = 0.0_dp
        call creep_strain_increment(params(), stress, 4.0_dp*pa, 0.5_dp, 30.0_dp, ev, es, de)
        dev = ev
        des = es
        call check(error, sum(de(1:3)), -dev, 'trace = -d eps_v', rel=1e-13_dp)
        if (allocated(error)) return
        mean = sum(de(1:3))/3.0_dp
        e = [de(1) - mean, de(2) - mean, de(3) - mean, 0.5_dp*de(4)]   ! tensor shear
        call check(error, sqrt(2.0_dp/3.0_dp*(e(1)**2 + e(2)**2 + e(3)**2 + 2.0_dp*e(4)**2)), &
                   des, 'generalised shear strain', rel=1e-13_dp)
        if (allocated(error)) return
        mean = sum(stress(1:3))/3.0_dp
        s = [stress(1) - mean, stress(2) - mean, stress(3) - mean, stress(4)]
        call check(error, e(2)/s(2), e(1)/s(1), 'e parallel to s (yy, xx)', rel=1e-13_dp)
        if (allocated(error)) return
        call check(error, e(4)/s(4), e(1)/s(1), 'e parallel to s (xy, xx)', rel=1e-13_dp)
        if (allocated(error)) return
        call check(error, de(2) < 0.0_dp, 'the major compression direction shortens')
    end subroutine test_split

    !> A point that crept under a high stress does not recover when the stress falls.
    subroutine test_no_recovery(error)
        type(error_t), allocatable, intent(out) :: error
        call check(error, creep_advance(params(), 0.003_dp, 0.001_dp, 100.0_dp), 0.003_dp, &
                   'strain kept when the final strain falls', abs=0.0_dp)
        if (allocated(error)) return
        call check(error, creep_advance(params(), 0.001_dp, 0.003_dp, 0.0_dp), 0.001_dp, &
                   'no change in zero time', abs=0.0_dp)
    end subroutine test_no_recovery
end module test_materials_creep
