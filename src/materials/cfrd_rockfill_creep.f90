!> Time-dependent (creep) deformation of rockfill: the exponential-decay law of Shen
!> Zhujiang with the final strains of Li Guoying's extension, the law used in most
!> analyses of high CFRDs (docs/theory.md, section 15), as pure functions.
!>
!> At constant stress the volumetric and the generalised shear creep strains grow as
!>     eps_v(t) = eps_vf (1 - exp(-alpha t)),   eps_s(t) = eps_sf (1 - exp(-alpha t)),
!> with the final strains
!>     eps_vf = b (sigma3/pa)^mc,               eps_sf = d (S / (1 - S))^l,
!> S the stress level of the Duncan-Chang E-B law. Under a stress that changes, the rate
!> form d eps/dt = alpha (eps_f(sigma) - eps) (the same curve at constant stress) is
!> integrated exactly over a step with eps_f frozen at the step's start; creep does not
!> recover when eps_f falls below the strain reached [choice: rockfill creep, particle
!> breakage and corner crushing, is irreversible]. The creep strain tensor follows
!> Prandtl-Reuss: one third of d eps_v on each normal component (compaction), and
!> 3/2 d eps_s s/q along the deviator s of the stress, q = sqrt(3/2 s:s).
!> Inside the law compression is positive; the returned strain increment is in the
!> finite-element convention (tension positive, engineering shear, order xx, yy, zz, xy).
module cfrd_rockfill_creep
    use cfrd_kinds, only: dp
    implicit none
    private

    public :: creep_params_t, creep_final_strains, creep_advance, creep_strain_increment
    public :: final_strain_step
    public :: relax_max

    !> The largest share of the mean stress or of the deviator that one step's creep may
    !> relax at a point held fully (creep_strain_increment) [choice].
    real(dp), parameter :: relax_max = 0.25_dp

    !> Parameters of the creep card (CREEP, after an EB material's two cards).
    type :: creep_params_t
        real(dp) :: alpha = 0.0_dp   !! decay rate, 1/day
        real(dp) :: b = 0.0_dp       !! final volumetric creep strain at sigma3 = pa, -
        real(dp) :: mc = 0.0_dp      !! exponent of sigma3/pa
        real(dp) :: d = 0.0_dp       !! final shear creep strain at S/(1 - S) = 1, -
        real(dp) :: l = 0.0_dp       !! exponent of S/(1 - S)
        real(dp) :: pa = 101.325_dp  !! atmospheric pressure, kPa
        real(dp) :: sigma3_floor = 10.1325_dp   !! kPa, floor on sigma3 (as the E-B law)
    end type creep_params_t

contains

    !> Final volumetric and shear creep strains at minor principal stress sigma3
    !> (compression positive, floored) and stress level `level` (0 <= S < 1).
    pure subroutine creep_final_strains(p, sigma3, level, ev_final, es_final)
        type(creep_params_t), intent(in) :: p
        real(dp), intent(in) :: sigma3, level
        real(dp), intent(out) :: ev_final, es_final
        real(dp) :: s
        ev_final = p%b*(max(sigma3, p%sigma3_floor)/p%pa)**p%mc
        s = min(max(level, 0.0_dp), 0.99_dp)
        es_final = 0.0_dp
        if (s > 0.0_dp) es_final = p%d*(s/(1.0_dp - s))**p%l
    end subroutine creep_final_strains

    !> The strain reached after dt days from `strain` towards `final`: exact for a final
    !> strain constant over the step; no change when `final` <= `strain` (no recovery).
    pure real(dp) function creep_advance(p, strain, final, dt) result(advanced)
        type(creep_params_t), intent(in) :: p
        real(dp), intent(in) :: strain, final, dt
        advanced = strain
        if (final > strain .and. dt > 0.0_dp) &
            advanced = strain + (final - strain)*one_minus_exp(p%alpha*dt)
    end function creep_advance

    !> 1 - exp(-x) without the cancellation of small x (x >= 0).
    pure real(dp) function one_minus_exp(x) result(y)
        real(dp), intent(in) :: x
        if (x < 1.0e-4_dp) then
            y = x*(1.0_dp - 0.5_dp*x*(1.0_dp - x/3.0_dp*(1.0_dp - 0.25_dp*x)))
        else
            y = 1.0_dp - exp(-x)
        end if
    end function one_minus_exp

    !> Creep strain increment d_strain (FE convention) over dt days at stress `stress`
    !> (tension positive, xx, yy, zz, xy) with minor principal stress sigma3 and stress
    !> level `level` from the E-B law; ev and es are the volumetric and shear creep strains
    !> reached so far (compression positive) and come back advanced.
    !>
    !> With `bulk` and `shear`, the tangent moduli that turn the step's creep into relaxed
    !> stresses, each part of the increment is limited so that, held fully, it would relax
    !> at most `relax_max` of the mean stress (bulk d eps_v <= relax_max p) or of the
    !> deviator (3 shear d eps_s <= relax_max q): the explicit step cannot overshoot where
    !> the final strain grows fast with the stress (S near 1); the rest of the creep comes
    !> in the next steps. Steps small against 1/alpha never reach the limit.
    pure subroutine creep_strain_increment(p, stress, sigma3, level, dt, ev, es, d_strain, &
                                           bulk, shear)
        type(creep_params_t), intent(in) :: p
        real(dp), intent(in) :: stress(4), sigma3, level, dt
        real(dp), intent(inout) :: ev, es
        real(dp), intent(out) :: d_strain(4)
        real(dp), intent(in), optional :: bulk, shear
        real(dp) :: share
        share = 0.0_dp
        if (dt > 0.0_dp) share = one_minus_exp(p%alpha*dt)
        call final_strain_step(p, stress, sigma3, level, share, ev, es, d_strain, bulk, shear)
    end subroutine creep_strain_increment

    !> The strain increment (FE convention) that takes the strains reached, ev and es, the
    !> share `share` (0..1) of the way to their final values at this stress, with the same
    !> flow rule and limits as creep_strain_increment. The wetting collapse of rockfill
    !> (Shen's wetting model, docs/theory.md section 16) is this step with the wetting
    !> parameters in p (b = CW, mc = NW, d = DW, l = 1) and the share of the wetting that
    !> remains taken in the increment.
    pure subroutine final_strain_step(p, stress, sigma3, level, share, ev, es, d_strain, &
                                      bulk, shear)
        type(creep_params_t), intent(in) :: p
        real(dp), intent(in) :: stress(4), sigma3, level, share
        real(dp), intent(inout) :: ev, es
        real(dp), intent(out) :: d_strain(4)
        real(dp), intent(in), optional :: bulk, shear
        real(dp) :: ev_final, es_final, dev, des, mean, s(4), q
        call creep_final_strains(p, sigma3, level, ev_final, es_final)
        ! no recovery: nothing when the final strain is below the strain reached (the
        ! difference of the advanced and the reached strain, as creep_advance)
        dev = 0.0_dp
        des = 0.0_dp
        if (ev_final > ev .and. share > 0.0_dp) dev = (ev + (ev_final - ev)*share) - ev
        if (es_final > es .and. share > 0.0_dp) des = (es + (es_final - es)*share) - es
        mean = sum(stress(1:3))/3.0_dp
        s = [stress(1) - mean, stress(2) - mean, stress(3) - mean, stress(4)]
        q = sqrt(1.5_dp*(s(1)**2 + s(2)**2 + s(3)**2 + 2.0_dp*s(4)**2))
        if (present(bulk)) dev = min(dev, relax_max*max(-mean, 0.0_dp)/bulk)
        if (present(shear)) des = min(des, relax_max*q/(3.0_dp*shear))
        ev = ev + dev
        es = es + des
        d_strain = 0.0_dp
        d_strain(1:3) = -dev/3.0_dp
        if (q > 0.0_dp .and. des > 0.0_dp) then
            ! 3/2 des s/q, the shear component doubled (engineering strain)
            d_strain(1:3) = d_strain(1:3) + 1.5_dp*des*s(1:3)/q
            d_strain(4) = 3.0_dp*des*s(4)/q
        end if
    end subroutine final_strain_step
end module cfrd_rockfill_creep
