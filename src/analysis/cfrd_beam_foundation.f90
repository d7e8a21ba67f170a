!> The slab on its cushion as a beam on an elastic (Winkler) foundation (docs/theory.md
!> section 13): how far an end disturbance of the slab (a clamped toe) reaches along it.
!> Hetenyi (Beams on Elastic Foundation, 1946, ch. II-III) [lit]: on a foundation of modulus
!> k (kPa/m, per unit area) a beam of width b and bending stiffness EI has the decay rate
!> lambda = (k b / (4 EI))^(1/4); every response of a semi-infinite beam to a force or a
!> moment at its end is a combination of e^(-lambda x) cos(lambda x) and
!> e^(-lambda x) sin(lambda x), so at x = pi / lambda it has fallen to e^(-pi) = 4.3 % of its
!> envelope at the end, and a beam longer than pi / lambda counts as long (its ends do not
!> interact). Vesic (1961) [lit]: the k of a beam on an elastic half-space (E_s, nu_s),
!> k = 0.65 (E_s b^4 / (EI))^(1/12) E_s / (b (1 - nu_s^2)). Pure functions, no state.
module cfrd_beam_foundation
    use cfrd_kinds, only: dp
    implicit none
    private

    public :: vesic_modulus, decay_rate, decay_radius

    real(dp), parameter :: pi = 3.14159265358979323846_dp

contains

    !> Vesic's modulus of subgrade reaction (kPa/m, per unit area under the beam) of a beam
    !> of width b (m) and bending stiffness ei (kN m^2) on an elastic half-space of modulus
    !> es (kPa) and Poisson ratio nus. 0 when es <= 0.
    pure real(dp) function vesic_modulus(es, nus, ei, b) result(k)
        real(dp), intent(in) :: es, nus, ei, b
        k = 0.0_dp
        if (es <= 0.0_dp .or. ei <= 0.0_dp .or. b <= 0.0_dp) return
        k = 0.65_dp*(es*b**4/ei)**(1.0_dp/12.0_dp)*es/(b*(1.0_dp - nus**2))
    end function vesic_modulus

    !> Hetenyi's decay rate lambda = (k b / (4 EI))^(1/4) (1/m) of a beam of width b (m) and
    !> bending stiffness ei (kN m^2) on a foundation of modulus k (kPa/m). 0 when k <= 0.
    pure real(dp) function decay_rate(k, ei, b) result(lambda)
        real(dp), intent(in) :: k, ei, b
        lambda = 0.0_dp
        if (k <= 0.0_dp .or. ei <= 0.0_dp) return
        lambda = sqrt(sqrt(k*b/(4.0_dp*ei)))
    end function decay_rate

    !> pi / lambda (m) for a slab strip of 1 m (plane strain, per m of dam) of thickness h
    !> (m) and concrete (e, nu) on an elastic foundation (es, nus), with `compliance` (m/kPa)
    !> of a layer in series between them (an interface: 1 / kn of a joint, t / M of a thin
    !> layer; 0: none): the strip bends as a plate, EI = e h^3 / (12 (1 - nu^2)) [choice];
    !> k of Vesic with b = 1 m, combined in series with the layer. Also returns k (kPa/m).
    !> 0 when the foundation has no stiffness (es <= 0).
    pure subroutine decay_radius(h, e, nu, es, nus, compliance, radius, k)
        real(dp), intent(in) :: h, e, nu, es, nus, compliance
        real(dp), intent(out) :: radius, k
        real(dp), parameter :: b = 1.0_dp
        real(dp) :: ei, lambda
        radius = 0.0_dp
        ei = e*h**3/(12.0_dp*(1.0_dp - nu**2))
        k = vesic_modulus(es, nus, ei, b)
        if (k <= 0.0_dp) return
        k = 1.0_dp/(1.0_dp/k + max(compliance, 0.0_dp))
        lambda = decay_rate(k, ei, b)
        if (lambda > 0.0_dp) radius = pi/lambda
    end subroutine decay_radius
end module cfrd_beam_foundation
