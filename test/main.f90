!> Test driver: `cfrd-tests` runs every suite; `cfrd-tests SUITE` one suite;
!> `cfrd-tests SUITE TEST` one test. Prints PASS/FAIL lines and `fortran: N passed, N failed`;
!> exits 1 when a test failed.
program cfrd_tests
    use cfrd_testing, only: unittest_t, run_suite
    use test_io_deck, only: collect_io_deck
    use test_io_card_schema, only: collect_io_card_schema
    use test_solver_sparse, only: collect_solver_sparse
    use test_solver_cholmod, only: collect_solver_cholmod
    use test_solver_schur, only: collect_solver_schur
    use test_solver_krylov, only: collect_solver_krylov
    use test_elements_quad4, only: collect_elements_quad4
    use test_elements_geometry, only: collect_elements_geometry
    use test_analysis_verification, only: collect_analysis_verification
    use test_io_results, only: collect_io_results
    use test_analysis_rockfill, only: collect_analysis_rockfill
    use test_materials_eb, only: collect_materials_eb
    use test_materials_creep, only: collect_materials_creep
    use test_core_dates, only: collect_core_dates
    use test_core_sha256, only: collect_core_sha256
    use test_core_omp, only: collect_core_omp
    use test_analysis_water, only: collect_analysis_water
    use test_analysis_interface, only: collect_analysis_interface
    use test_analysis_slab, only: collect_analysis_slab
    use test_contact_mortar, only: collect_contact_mortar
    use test_contact_hertz, only: collect_contact_hertz
    use test_analysis_increment, only: collect_analysis_increment
    use test_analysis_pjoint, only: collect_analysis_pjoint
    use test_io_fast_format, only: collect_io_fast_format
    implicit none
    character(len=64) :: only_suite, only_test
    type(unittest_t), allocatable :: tests(:)
    integer :: npass, nfail

    only_suite = ''
    only_test = ''
    if (command_argument_count() >= 1) call get_command_argument(1, only_suite)
    if (command_argument_count() >= 2) call get_command_argument(2, only_test)
    npass = 0
    nfail = 0

    if (wanted('io_deck')) then
        call collect_io_deck(tests)
        call run_suite('io_deck', tests, only_test, npass, nfail)
    end if
    if (wanted('io_card_schema')) then
        call collect_io_card_schema(tests)
        call run_suite('io_card_schema', tests, only_test, npass, nfail)
    end if
    if (wanted('solver_sparse')) then
        call collect_solver_sparse(tests)
        call run_suite('solver_sparse', tests, only_test, npass, nfail)
    end if
    if (wanted('solver_cholmod')) then
        call collect_solver_cholmod(tests)
        call run_suite('solver_cholmod', tests, only_test, npass, nfail)
    end if
    if (wanted('solver_schur')) then
        call collect_solver_schur(tests)
        call run_suite('solver_schur', tests, only_test, npass, nfail)
    end if
    if (wanted('solver_krylov')) then
        call collect_solver_krylov(tests)
        call run_suite('solver_krylov', tests, only_test, npass, nfail)
    end if
    if (wanted('elements_quad4')) then
        call collect_elements_quad4(tests)
        call run_suite('elements_quad4', tests, only_test, npass, nfail)
    end if
    if (wanted('elements_geometry')) then
        call collect_elements_geometry(tests)
        call run_suite('elements_geometry', tests, only_test, npass, nfail)
    end if
    if (wanted('analysis_verification')) then
        call collect_analysis_verification(tests)
        call run_suite('analysis_verification', tests, only_test, npass, nfail)
    end if
    if (wanted('materials_eb')) then
        call collect_materials_eb(tests)
        call run_suite('materials_eb', tests, only_test, npass, nfail)
    end if
    if (wanted('core_dates')) then
        call collect_core_dates(tests)
        call run_suite('core_dates', tests, only_test, npass, nfail)
    end if
    if (wanted('core_sha256')) then
        call collect_core_sha256(tests)
        call run_suite('core_sha256', tests, only_test, npass, nfail)
    end if
    if (wanted('core_omp')) then
        call collect_core_omp(tests)
        call run_suite('core_omp', tests, only_test, npass, nfail)
    end if
    if (wanted('materials_creep')) then
        call collect_materials_creep(tests)
        call run_suite('materials_creep', tests, only_test, npass, nfail)
    end if
    if (wanted('analysis_rockfill')) then
        call collect_analysis_rockfill(tests)
        call run_suite('analysis_rockfill', tests, only_test, npass, nfail)
    end if
    if (wanted('analysis_water')) then
        call collect_analysis_water(tests)
        call run_suite('analysis_water', tests, only_test, npass, nfail)
    end if
    if (wanted('analysis_interface')) then
        call collect_analysis_interface(tests)
        call run_suite('analysis_interface', tests, only_test, npass, nfail)
    end if
    if (wanted('analysis_slab')) then
        call collect_analysis_slab(tests)
        call run_suite('analysis_slab', tests, only_test, npass, nfail)
    end if
    if (wanted('contact_mortar')) then
        call collect_contact_mortar(tests)
        call run_suite('contact_mortar', tests, only_test, npass, nfail)
    end if
    if (wanted('contact_hertz')) then
        call collect_contact_hertz(tests)
        call run_suite('contact_hertz', tests, only_test, npass, nfail)
    end if
    if (wanted('analysis_increment')) then
        call collect_analysis_increment(tests)
        call run_suite('analysis_increment', tests, only_test, npass, nfail)
    end if
    if (wanted('io_results')) then
        call collect_io_results(tests)
        call run_suite('io_results', tests, only_test, npass, nfail)
    end if
    if (wanted('analysis_pjoint')) then
        call collect_analysis_pjoint(tests)
        call run_suite('analysis_pjoint', tests, only_test, npass, nfail)
    end if
    if (wanted('io_fast_format')) then
        call collect_io_fast_format(tests)
        call run_suite('io_fast_format', tests, only_test, npass, nfail)
    end if

    write (*, '(a,i0,a,i0,a)') 'fortran: ', npass, ' passed, ', nfail, ' failed'
    if (nfail > 0) error stop 1

contains

    logical function wanted(suite)
        character(len=*), intent(in) :: suite
        wanted = len_trim(only_suite) == 0 .or. only_suite == suite
    end function wanted
end program cfrd_tests
