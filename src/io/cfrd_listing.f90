!> The printed listing, in the manner of the legacy dam codes: the input echoed with line
!> numbers, then per stage tables of node displacements, element stresses at centroids with
!> principal stresses, reactions with their sum against the applied load, and the solver's
!> figures (docs/results.md). Writers format; they compute nothing but sums for display.
!> The per-stage tables come from the stages' summaries, the full tables from the last
!> stage's results (the run streams every stage's results to the HDF5 file).
module cfrd_listing
    use cfrd_kinds, only: dp
    use cfrd_error, only: error_t, fatal_error, io_error
    use cfrd_version, only: cfrd_version_string
    use cfrd_model, only: model_t, law_name, dry_level, law_goodman, law_pjoint, &
                          is_joint_kind, scheme_name, search_name, scheme_mortar
    use cfrd_contact, only: friction_group_ratio
    use cfrd_contact_roles, only: mean_face
    use cfrd_results, only: stage_result_t, body_extremes_t
    use cfrd_stage_summary, only: stage_summary_t
    use cfrd_columns, only: csv_real, date_of, level_of, run_id_comment
    use cfrd_interface_io, only: write_opening_history, write_slab_history, &
                                 write_interface_tables, &
                                 write_opening_summary
    use cfrd_effects, only: effects_text
    use cfrd_pjoint_io, only: write_pjoint_table
    use cfrd_run_identity, only: run_identity_t
    use cfrd_fast_format, only: put_int, put_fixed, put_sci, next_line, write_lines, &
                                block_chars
    implicit none
    private

    public :: write_listing, write_summary, write_gauge_csv, resolution_note

    character(len=*), parameter :: rule = repeat('-', 100)

contains

    !> Write the listing of a run to `path`: `summaries` of every stage, `last` the full
    !> results of the last one, `wall_time` (s) of the analysis; the banner names the run
    !> (`identity`: run id and the deck's SHA-256) when given.
    subroutine write_listing(path, model, summaries, last, wall_time, error, identity)
        character(len=*), intent(in) :: path
        type(model_t), intent(in) :: model
        type(stage_summary_t), intent(in) :: summaries(:)
        type(stage_result_t), intent(in) :: last
        real(dp), intent(in) :: wall_time
        type(error_t), allocatable, intent(out) :: error
        type(run_identity_t), intent(in), optional :: identity
        integer :: unit, stat
        character(len=256) :: msg
        open (newunit=unit, file=path, status='replace', action='write', iostat=stat, &
              iomsg=msg)
        if (stat /= 0) then
            call fatal_error(error, 'cannot write the listing '//path//': '//trim(msg), io_error)
            return
        end if
        call write_banner(unit, model, identity)
        call write_echo(unit, model)
        call write_model_summary(unit, model)
        call write_stage_table(unit, model, summaries)
        call write_gauge_tables(unit, model, summaries)
        call write_opening_history(unit, model, summaries)
        call write_slab_history(unit, model, summaries)
        call write_pjoint_table(unit, model, summaries)
        ! The full tables of the last stage; every stage's state is in the HDF5 file.
        call write_stage(unit, model, last, size(summaries))
        call write_solver(unit, model, summaries)
        write (unit, '(/,a,f10.3,a)', iostat=stat, iomsg=msg) ' TOTAL ANALYSIS TIME', &
            wall_time, ' s'
        if (stat /= 0) then
            call fatal_error(error, 'cannot write the listing '//path//': '//trim(msg), io_error)
        end if
        close (unit)
    end subroutine write_listing

    subroutine write_banner(unit, model, identity)
        integer, intent(in) :: unit
        type(model_t), intent(in) :: model
        type(run_identity_t), intent(in), optional :: identity
        character(len=8) :: date
        character(len=10) :: time
        call date_and_time(date, time)
        write (unit, '(a)') rule, &
            ' CFRD '//cfrd_version_string//'   staged finite-element analysis of '// &
            'concrete-faced rockfill dams', &
            ' RUN OF '//date(1:4)//'-'//date(5:6)//'-'//date(7:8)//' '//time(1:2)//':'// &
            time(3:4)//':'//time(5:6)
        ! The run id ties the listing to the other files of its result set (docs/results.md).
        if (present(identity)) write (unit, '(a)') ' RUN ID '//identity%run_id, &
            ' DECK SHA-256 '//identity%deck_sha256
        write (unit, '(a)') ' DECK   '//model%deck_file, &
            ' TITLE  '//model%title, rule
    end subroutine write_banner

    subroutine write_echo(unit, model)
        integer, intent(in) :: unit
        type(model_t), intent(in) :: model
        integer :: start, i, line
        write (unit, '(/,a,/,a)') ' ECHO OF INPUT', &
            '  LINE  ----+----1----+----2----+----3----+----4----+----5----+----6----+----7'// &
            '----+----8'
        start = 1
        line = 0
        do i = 1, len(model%deck_text) + 1
            if (i > len(model%deck_text)) then
                if (start > len(model%deck_text)) exit
            else if (model%deck_text(i:i) /= achar(10)) then
                cycle
            end if
            line = line + 1
            write (unit, '(i6,2x,a)') line, model%deck_text(start:i - 1)
            start = i + 1
        end do
    end subroutine write_echo

    subroutine write_model_summary(unit, model)
        integer, intent(in) :: unit
        type(model_t), intent(in) :: model
        integer :: m
        write (unit, '(/,a)') ' CONTROL'
        write (unit, '(a,t40,a)') '   analysis', 'plane strain'
        write (unit, '(a,t40,a)') '   units', 'm, kN, kPa ('//model%units//')'
        write (unit, '(a,t40,i10)') '   nodes', model%mesh%nnode
        write (unit, '(a,t40,i10)') '   elements', model%mesh%nelem
        write (unit, '(a,t40,i10)') '   materials', size(model%materials)
        write (unit, '(a,t40,f10.3,a)') '   atmospheric pressure pa', model%pa, ' kPa'
        write (unit, '(a,t40,f10.3,a)') '   unit weight of water', model%gamma_w, ' kN/m3'
        write (unit, '(a,t40,a)') '   effects', effects_text(model%effects)
        write (unit, '(/,a,/,a)') ' MATERIALS', &
            '   MAT LAW                   E (kPa)        NU   GAMMA (kN/m3)  LABEL'
        do m = 1, size(model%materials)
            associate (mat => model%materials(m))
                write (unit, '(i6,1x,a10,es18.6,f10.4,f16.4,2x,a)') m, law_name(mat%law), &
                    mat%youngs_modulus, mat%poisson_ratio, mat%unit_weight, mat%label
                if (mat%law == law_goodman) write (unit, '(8x,a,2es11.3,a,f8.1,a,f6.3,a,f6.3,a,'// &
                    'f6.2,a,es10.3,a,a)') 'kn compression / tension', mat%kn_compression, &
                    mat%kn_tension, ' kPa/m, k1', mat%k1, ', n1', mat%n1, ', Rf1', mat%rf1, &
                    ', phi', mat%phi, ' deg, sigma_n floor', mat%sigma_n_floor, ' kPa, tension', &
                    trim(merge(' cut off        ', ' carried with kn', mat%tension_cutoff))
                if (mat%law == law_pjoint) write (unit, '(8x,a,3es11.3,a)') &
                    'kn compression / tension (waterstops), ks', mat%kn_compression, &
                    mat%kn_tension, mat%ks_joint, ' kPa/m'
            end associate
        end do
        if (allocated(model%contact_pairs)) then
            if (size(model%contact_pairs) > 0) then
                write (unit, '(/,a,/,a)') ' CONTACT PAIRS', '  PAIR SLAVE      MASTER     '// &
                    '  FACES         MU    TOL (m) SCHEME SEARCH CAST'
                do m = 1, size(model%contact_pairs)
                    associate (pair => model%contact_pairs(m))
                        write (unit, '(i6,1x,a10,1x,a10,i4,a,i4,f11.4,es11.3,1x,a6,1x,a6,1x,a)') &
                            m, model%surfaces(pair%slave)%name, &
                            model%surfaces(pair%master)%name, &
                            size(model%surfaces(pair%slave)%element), ' /', &
                            size(model%surfaces(pair%master)%element), pair%friction, &
                            pair%tolerance, scheme_name(pair%scheme), search_name(pair%search), &
                            trim(merge('yes', 'no ', pair%cast))
                        ! a slave much finer than its master: friction per master segment
                        if (pair%friction > 0.0_dp .and. pair%scheme == scheme_mortar .and. &
                            mean_face(model, pair%master) >= friction_group_ratio* &
                            mean_face(model, pair%slave)) write (unit, '(7x,a,f6.1,a)') &
                            'the slave''s faces are', mean_face(model, pair%master)/ &
                            mean_face(model, pair%slave), ' times shorter than the master''s: '// &
                            'friction per master segment (docs/theory.md section 14)'
                        if (pair%swapped) write (unit, '(7x,5a,f6.3,3a,f6.3,a)') 'roles '// &
                            'swapped: the card''s slave ', trim(model%surfaces(pair%master)%name), &
                            ' is much finer than its master ', &
                            trim(model%surfaces(pair%slave)%name), ' (mean face ', &
                            mean_face(model, pair%master), ' m against ', &
                            trim(model%surfaces(pair%slave)%name), '''s ', &
                            mean_face(model, pair%slave), ' m): '
                        if (pair%swapped) write (unit, '(9x,3a)') &
                            trim(model%surfaces(pair%slave)%name), ' carries the multipliers, '// &
                            'results at the nodes of ', trim(model%surfaces(pair%master)%name)// &
                            ' (ROLES ASIS keeps the card''s roles; docs/theory.md section 14)'
                    end associate
                end do
            end if
        end if
        if (allocated(model%warnings)) then
            if (size(model%warnings) > 0) then
                write (unit, '(/,a)') ' WARNINGS'
                do m = 1, size(model%warnings)
                    write (unit, '(3x,a)') trim(model%warnings(m))
                end do
            end if
        end if
    end subroutine write_model_summary

    !> One line per stage: what it did, how the solution went, the extreme displacements.
    subroutine write_stage_table(unit, model, summaries)
        integer, intent(in) :: unit
        type(model_t), intent(in) :: model
        type(stage_summary_t), intent(in) :: summaries(:)
        integer :: s
        write (unit, '(/,a,/,a,/,a)') rule, ' STAGES', rule
        write (unit, '(a)') '  STAGE LABEL                      DATE       WATER (m) ACTIVE'// &
            ' INC FACT ITER   MAX RESID  MAX SETTL (m)   NODE     MAX UX (m)   NODE'// &
            '     MIN UX (m)   NODE  S>=0.95'
        do s = 1, size(summaries)
            associate (st => summaries(s))
                write (unit, '(i7,1x,a26,1x,a10,a10,i7,i4,i5,i5,es12.3,3(es15.5,i7),i9)') s, &
                    st%name, date_of(st), level_of(st), st%active_elements, st%increments, &
                    st%factorisations, st%iterations, st%max_residual, &
                    st%settlement, st%settlement_node, st%ux_max, st%ux_max_node, &
                    st%ux_min, st%ux_min_node, st%near_failure
            end associate
        end do
        write (unit, '(a,i0,a)') '  (', model%mesh%nelem, ' elements in the mesh; displacements'// &
            ' since each node''s placement, RESETs added back; WATER: reservoir level at the'// &
            ' end; MAX RESID = |out-of-balance force| / |load| after an increment; S>=0.95:'// &
            ' elements near failure)'
        if (any(summaries%unbalanced > 0)) write (unit, '(a,i0,a,i0,a)') '  WARNING: ', &
            sum(summaries%unbalanced), ' increment(s) in ', count(summaries%unbalanced > 0), &
            ' stage(s) accepted with MAX RESID above ERRTOL at the depth limit of the error'// &
            ' control (CONTROL ERRCTL; each stage''s section names the first)'
    end subroutine write_stage_table

    !> Per gauge and stage: horizontal displacement, then settlement, since placement.
    subroutine write_gauge_tables(unit, model, summaries)
        integer, intent(in) :: unit
        type(model_t), intent(in) :: model
        type(stage_summary_t), intent(in) :: summaries(:)
        integer :: s, g, k
        character(len=*), parameter :: what(2) = [character(len=70) :: &
            ' GAUGES: HORIZONTAL DISPLACEMENT UX (m, + towards +x, downstream)', &
            ' GAUGES: SETTLEMENT -UY (m, + downwards)']
        if (.not. allocated(model%gauges)) return
        if (size(model%gauges) == 0) return
        write (unit, '(/,a,/,a,/,a)') rule, ' GAUGES (displacements since placement)', rule
        write (unit, '(a)') '   NAME         NODE          X (m)          Y (m)  LABEL'
        do g = 1, size(model%gauges)
            associate (gauge => model%gauges(g))
                write (unit, '(3x,a10,i7,2f15.3,2x,a)') gauge%name, gauge%node, &
                    model%mesh%x(:, gauge%node), gauge%label
            end associate
        end do
        do k = 1, 2
            write (unit, '(/,a)') trim(what(k))
            write (unit, '(a,*(a12))') '  STAGE DATE       WATER (m)', &
                (adjustr(trim(model%gauges(g)%name)), g = 1, size(model%gauges))
            do s = 1, size(summaries)
                associate (st => summaries(s))
                    write (unit, '(i7,1x,a10,a10,*(f12.4))') s, date_of(st), level_of(st), &
                        (merge(1.0_dp, -1.0_dp, k == 1)*st%gauge_u(k, g) + 0.0_dp, &
                         g = 1, size(model%gauges))
                end associate
            end do
        end do
    end subroutine write_gauge_tables

    !> The gauge histories as CSV (one row per stage) at `path`; a first comment line
    !> '# cfrd run_id ID' when `run_id` is given.
    subroutine write_gauge_csv(path, model, summaries, error, run_id)
        character(len=*), intent(in) :: path
        type(model_t), intent(in) :: model
        type(stage_summary_t), intent(in) :: summaries(:)
        type(error_t), allocatable, intent(out) :: error
        character(len=*), intent(in), optional :: run_id
        integer :: unit, stat, s, g
        character(len=256) :: msg
        character(len=:), allocatable :: level
        open (newunit=unit, file=path, status='replace', action='write', iostat=stat, &
              iomsg=msg)
        if (stat /= 0) then
            call fatal_error(error, 'cannot write the gauge histories '//path//': '// &
                             trim(msg), io_error)
            return
        end if
        if (present(run_id)) write (unit, '(a)') run_id_comment(run_id)
        write (unit, '(a)', advance='no') 'stage,label,date,water_level_m'
        do g = 1, size(model%gauges)
            write (unit, '(a)', advance='no') ','//trim(model%gauges(g)%name)//'_ux_m,'// &
                trim(model%gauges(g)%name)//'_settlement_m'
        end do
        write (unit, '(a)') ''
        do s = 1, size(summaries)
            associate (st => summaries(s))
                level = ''
                if (st%water_level /= dry_level) level = trim(adjustl(level_of(st)))
                write (unit, '(i0,a)', advance='no') s, ',"'//st%name//'",'// &
                    trim(adjustl(date_of(st)))//','//level
                do g = 1, size(model%gauges)
                    write (unit, '(a)', advance='no') ','//csv_real(st%gauge_u(1, g))//','// &
                        csv_real(-st%gauge_u(2, g))
                end do
                write (unit, '(a)', iostat=stat, iomsg=msg) ''
            end associate
        end do
        close (unit)
        if (stat /= 0) call fatal_error(error, 'cannot write the gauge histories '//path// &
                                        ': '//trim(msg), io_error)
    end subroutine write_gauge_csv

    subroutine write_stage(unit, model, stage, number)
        integer, intent(in) :: unit, number
        type(model_t), intent(in) :: model
        type(stage_result_t), intent(in) :: stage
        integer :: node, e, k, pos
        real(dp) :: imbalance
        character(len=:), allocatable :: buf
        write (unit, '(/,a,/,a,i4,2a,/,a)') rule, ' STAGE', number, '   ', stage%name, rule
        if (allocated(stage%warning)) write (unit, '(/,a,i0,a,/,3x,a)') ' WARNING: ', &
            stage%unbalanced, ' increment(s) accepted out of balance above ERRTOL; the first:', &
            stage%warning
        write (unit, '(/,a,/,a)') ' NODE DISPLACEMENTS (UX, UY since the last RESET; TOTAL:'// &
            ' since placement)', &
            '   NODE          X (m)          Y (m)         UX (m)         UY (m)'// &
            '   UX TOTAL (m)   UY TOTAL (m)'
        ! The long tables: the characters of the formats in the comments, made by
        ! cfrd_fast_format into blocks of lines written at once (docs/performance.md (r)).
        allocate (character(len=block_chars) :: buf)
        pos = 1
        do node = 1, model%mesh%nnode                   ! (i7,2f15.4,4es15.6)
            call put_int(buf, pos, node, 7)
            call put_fixed(buf, pos, model%mesh%x(1, node), 15, 4)
            call put_fixed(buf, pos, model%mesh%x(2, node), 15, 4)
            call put_sci(buf, pos, stage%displacement(1, node), 15, 6)
            call put_sci(buf, pos, stage%displacement(2, node), 15, 6)
            call put_sci(buf, pos, stage%displacement_total(1, node), 15, 6)
            call put_sci(buf, pos, stage%displacement_total(2, node), 15, 6)
            call next_line(unit, buf, pos)
        end do
        call write_lines(unit, buf, pos)
        write (unit, '(/,a,/,a,/,a)') ' ELEMENT STRESSES AT CENTROIDS (kPa, tension positive;'// &
            ' ANGLE of SIGMA1 from x, degrees)', &
            '   ELEM MAT          SXX          SYY          SZZ          SXY       SIGMA1'// &
            '       SIGMA3   ANGLE'
        do e = 1, model%mesh%nelem                      ! (i7,i4,6es13.4,f8.2)
            ! Joints carry tractions, not stresses: they are in the INTERFACE table.
            if (is_joint_kind(model%mesh%kind(e))) cycle
            call put_int(buf, pos, e, 7)
            call put_int(buf, pos, model%mesh%material(e), 4)
            do k = 1, size(stage%stress_centroid, 1)
                call put_sci(buf, pos, stage%stress_centroid(k, e), 13, 4)
            end do
            call put_sci(buf, pos, stage%principal(1, e), 13, 4)
            call put_sci(buf, pos, stage%principal(2, e), 13, 4)
            call put_fixed(buf, pos, stage%principal(3, e), 8, 2)
            call next_line(unit, buf, pos)
        end do
        call write_lines(unit, buf, pos)
        call write_interface_tables(unit, model, stage)
        if (allocated(stage%extremes)) then
            write (unit, '(/,a,/,a)') ' EXTREME STRESSES PER BODY (at centroids; the slab''s '// &
                'sections for its fibre stress)', &
                ' quantity                          value   elem/sect         x (m)         y (m)'
            call write_body_extremes(unit, model, stage)
        end if
        write (unit, '(/,a,/,a)') ' REACTIONS (kN/m)', &
            '   NODE             RX             RY'
        do node = 1, model%mesh%nnode                   ! (i7,2es15.6)
            if (.not. any(model%fixed(:, node))) cycle
            call put_int(buf, pos, node, 7)
            call put_sci(buf, pos, stage%reaction(1, node), 15, 6)
            call put_sci(buf, pos, stage%reaction(2, node), 15, 6)
            call next_line(unit, buf, pos)
        end do
        call write_lines(unit, buf, pos)
        imbalance = norm2(stage%applied_load + stage%reaction_sum)/ &
                    max(norm2(stage%applied_load), tiny(1.0_dp))
        write (unit, '(a,2es15.6)') '    SUM', stage%reaction_sum
        write (unit, '(a,2es15.6)') ' APPLIED', stage%applied_load
        write (unit, '(a,es10.2)') ' RELATIVE IMBALANCE |APPLIED + REACTIONS| / |APPLIED| =', &
            imbalance
    end subroutine write_stage

    !> The solver's figures: the last stage's and the sums over all stages.
    subroutine write_solver(unit, model, summaries)
        integer, intent(in) :: unit
        type(model_t), intent(in) :: model
        type(stage_summary_t), intent(in) :: summaries(:)
        character(len=*), parameter :: counts = '(a,t40,i12,i14)', times = '(a,t40,f12.4,f14.4,a)'
        logical :: contact
        contact = .false.
        if (allocated(model%contact_pairs)) contact = size(model%contact_pairs) > 0
        associate (st => summaries(size(summaries))%stats, all => summaries%stats)
            write (unit, '(/,a,t40,a12,a14)') ' SOLVER', 'last stage', 'all stages'
            write (unit, '(a,t40,i12)') '   equations', st%neq
            write (unit, '(a,t40,i12)') '   matrix nonzeros', st%nnz
            write (unit, '(a,t40,i12)') '   factor nonzeros (L+U, or L)', st%lu_nnz
            write (unit, '(a,t40,es12.3)') '   reciprocal condition estimate', st%rcond
            write (unit, counts) '   increments', summaries(size(summaries))%increments, &
                sum(summaries%increments)
            write (unit, counts) '   sparse patterns built', st%patterns, sum(all%patterns)
            write (unit, counts) '   symbolic factorisations', st%analyses, sum(all%analyses)
            write (unit, counts) '     of which made ahead (2nd thread)', st%analyses_ahead, &
                sum(all%analyses_ahead)
            write (unit, counts) '   numeric factorisations', &
                summaries(size(summaries))%factorisations, sum(summaries%factorisations)
            write (unit, counts) '     of which CHOLMOD (L L^T)', st%cholesky, &
                sum(all%cholesky)
            write (unit, counts) '   CHOLMOD declined (not pos. def.)', &
                st%cholesky_declined, sum(all%cholesky_declined)
            if (contact) then
                write (unit, counts) '   factorisation updates', st%updates, sum(all%updates)
                write (unit, counts) '   contact iterations (solves)', st%contact_iterations, &
                    sum(all%contact_iterations)
                write (unit, counts) '   regularised factorisations', st%regularised, &
                    sum(all%regularised)
                write (unit, counts) '   slave nodes held in stick (most)', st%held, &
                    maxval(all%held)
                write (unit, '(a,t40,es12.3,es14.3)') '   held nodes: excess / pressure', &
                    st%held_excess, maxval(all%held_excess)
            end if
            write (unit, times) '   pattern', st%t_pattern, sum(all%t_pattern), ' s'
            write (unit, times) '   assembly', st%t_assembly, sum(all%t_assembly), ' s'
            write (unit, times) '   symbolic factorisation', st%t_symbolic, &
                sum(all%t_symbolic), ' s'
            write (unit, times) '   numeric factorisation', st%t_numeric, sum(all%t_numeric), &
                ' s'
            if (contact) write (unit, times) '   factorisation updates', st%t_update, &
                sum(all%t_update), ' s'
            write (unit, times) '   solve', st%t_solve, sum(all%t_solve), ' s'
            if (contact) write (unit, times) '   contact search and active set', &
                st%t_contact, sum(all%t_contact), ' s'
        end associate
    end subroutine write_solver

    !> A short result table for the terminal: extreme displacements (since placement) and
    !> principal stresses and where they occur, the reaction balance, the gauge histories
    !> (one row per calendar date: the last stage of each date) and the solver's times.
    subroutine write_summary(unit, model, summaries, stage, wall_time)
        integer, intent(in) :: unit
        type(model_t), intent(in) :: model
        type(stage_summary_t), intent(in) :: summaries(:)
        type(stage_result_t), intent(in) :: stage    !! the last stage
        real(dp), intent(in) :: wall_time            !! s, the analysis
        integer :: node, e, s, g
        real(dp) :: imbalance
        associate (mesh => model%mesh)
            write (unit, '(a)') 'cfrd '//cfrd_version_string//': '//model%deck_file// &
                ' -- '//model%title
            write (unit, '(a,i0,a,i0,a,i0,a)') '  ', mesh%nnode, ' nodes, ', mesh%nelem, &
                ' elements, ', stage%stats%neq, ' equations'
            write (unit, '(a)') '  at the end of the last stage '//trim(date_of(stage))// &
                ', reservoir '//trim(adjustl(level_of(stage)))//'; displacements since placement'
            write (unit, '(a)') '  quantity                          value   node/elem'// &
                '         x (m)         y (m)'
            node = minloc(stage%displacement_total(2, :), dim=1)
            write (unit, '(a,es14.5,i12,2f14.3)') '  max settlement (-uy), m    ', &
                -stage%displacement_total(2, node), node, mesh%x(:, node)
            node = maxloc(stage%displacement_total(1, :), dim=1)
            write (unit, '(a,es14.5,i12,2f14.3)') '  max ux (+x), m             ', &
                stage%displacement_total(1, node), node, mesh%x(:, node)
            node = minloc(stage%displacement_total(1, :), dim=1)
            write (unit, '(a,es14.5,i12,2f14.3)') '  min ux (-x), m             ', &
                stage%displacement_total(1, node), node, mesh%x(:, node)
            if (allocated(stage%extremes)) then
                call write_body_extremes(unit, model, stage)
            else
                e = maxloc(stage%principal(1, :), dim=1)
                write (unit, '(a,es14.5,i12,2f14.3)') '  max sigma1 (tension +), kPa', &
                    stage%principal(1, e), e, centroid(e)
                e = minloc(stage%principal(2, :), dim=1)
                write (unit, '(a,es14.5,i12,2f14.3)') '  min sigma3, kPa            ', &
                    stage%principal(2, e), e, centroid(e)
            end if
            imbalance = norm2(stage%applied_load + stage%reaction_sum)/ &
                        max(norm2(stage%applied_load), tiny(1.0_dp))
            write (unit, '(a,2es14.5)') '  applied load (x, y), kN/m  ', stage%applied_load
            write (unit, '(a,2es14.5)') '  sum of reactions, kN/m     ', stage%reaction_sum
            write (unit, '(a,es14.5)') '  relative imbalance         ', imbalance
            if (allocated(model%gauges)) then
                if (size(model%gauges) > 0) then
                    write (unit, '(a)') '  gauges: ux (m, + downstream) / settlement (m, + down)'
                    write (unit, '(a,*(a16))') '  date       water (m)', &
                        (adjustr(trim(model%gauges(g)%name)//'   '), g = 1, size(model%gauges))
                    do s = 1, size(summaries)
                        if (s < size(summaries)) then
                            if (date_of(summaries(s)) == date_of(summaries(s + 1))) cycle
                        end if
                        associate (st => summaries(s))
                            write (unit, '(2x,a10,a10,*(f8.3,"/",f7.3))') date_of(st), &
                                level_of(st), (st%gauge_u(1, g) + 0.0_dp, &
                                               -st%gauge_u(2, g) + 0.0_dp, &
                                               g = 1, size(model%gauges))
                        end associate
                    end do
                end if
            end if
            call write_opening_summary(unit, model, summaries)
            write (unit, '(a,f10.4,a,f8.4,a,f8.4,a,i0,a,i0,a)') '  time', wall_time, &
                ' s (assembly', sum(summaries%stats%t_assembly), ' s, factorisation', &
                sum(summaries%stats%t_symbolic + summaries%stats%t_numeric), &
                ' s, ', size(summaries), ' stages, ', sum(summaries%increments), &
                ' increments)'
        end associate
    contains
        function centroid(e) result(c)
            integer, intent(in) :: e
            real(dp) :: c(2)
            c = sum(model%mesh%x(:, model%mesh%conn(:, e)), dim=2)/4.0_dp
        end function centroid
    end subroutine write_summary

    !> Extreme stresses per body (slab, rockfill) at centroids, the slab's largest fibre
    !> and membrane stress N/h, and a note naming the singular points left out and why
    !> (docs/theory.md s. 13).
    subroutine write_body_extremes(unit, model, stage)
        integer, intent(in) :: unit
        type(model_t), intent(in) :: model
        type(stage_result_t), intent(in) :: stage
        integer :: b, k
        character(len=*), parameter :: fmt = '(a,es14.5,i12,2f14.3)'
        do b = 1, size(stage%extremes)
            associate (ex => stage%extremes(b))
                if (ex%max_element == 0) cycle
                write (unit, fmt) '  '//ex%body//' max sigma1, kPa  ', ex%max_sigma1, &
                    ex%max_element, centroid_of(model, ex%max_element)
                write (unit, fmt) '  '//ex%body//' min sigma3, kPa  ', ex%min_sigma3, &
                    ex%min_element, centroid_of(model, ex%min_element)
                if (ex%max_section > 0) then
                    write (unit, '(a,es14.5,i12,2f14.3,a,f7.3,a)') &
                        '  '//ex%body//' max fibre, kPa   ', ex%max_fibre, ex%max_section, &
                        stage%slab%section_x(ex%max_section), &
                        stage%slab%section_y(ex%max_section), '  (section; ratio to f_t', &
                        stage%slab%crack_ratio(ex%max_section), ')'
                    write (unit, '(a,es14.5,i12,2f14.3,a)') &
                        '  '//ex%body//' max N/h, kPa     ', ex%max_membrane, &
                        ex%max_membrane_section, &
                        stage%slab%section_x(ex%max_membrane_section), &
                        stage%slab%section_y(ex%max_membrane_section), &
                        '  (section; membrane stress N/A, the mean of the two fibres)'
                    write (unit, '(a)') resolution_note(ex)
                end if
            end associate
        end do
        if (size(stage%singular_nodes) == 0) then
            write (unit, '(a)') '  no slab node is held by a support: no element left out'
            return
        end if
        write (unit, '(a,i0,a,i0,a)') '  left out: ', stage%extremes(1)%left_out, ' slab and ', &
            stage%extremes(2)%left_out, ' rockfill elements, and the slab sections (max fibre,'// &
            ' max N/h), with their centroid within a radius of a slab node on a support,'// &
            ' where the stresses are singular (they grow as the mesh is refined) and the'// &
            ' slab is disturbed: the larger of 2 h and pi/lambda, the reach of an end'// &
            ' disturbance of the slab as a beam on its cushion as an elastic foundation'// &
            ' (Hetenyi 1946, k of Vesic 1961; docs/theory.md section 13):'
        write (unit, '(a,*(1x,i0))') '    nodes', stage%singular_nodes
        associate (x => model%mesh%x(:, stage%singular_nodes))
            write (unit, '(a,2f10.3,a,2f10.3,a,2f7.3,a)') '    x', minval(x(1, :)), &
                maxval(x(1, :)), ' m, y', minval(x(2, :)), maxval(x(2, :)), ' m; radius', &
                minval(stage%singular_radius), maxval(stage%singular_radius), ' m'
        end associate
        k = maxloc(stage%singular_radius, dim=1)
        associate (w => stage%singular_why(k))
            if (w%support == 0) then
                write (unit, '(a,f7.3,a)') '    2 h =', 2.0_dp*w%thickness, &
                    ' m (no elastic slab on a rockfill element found: pi/lambda not known)'
            else
                write (unit, '(a,f7.3,a,f7.3,a,i0,a,es11.4,a,es11.4,a)') '    largest: 2 h =', &
                    2.0_dp*w%thickness, ' m, pi/lambda =', w%decay, ' m (support element ', &
                    w%support, ', E-B initial or elastic modulus', w%es, ' kPa; k =', &
                    w%modulus, ' kPa/m)'
            end if
        end associate
    end subroutine write_body_extremes

    !> The summary's line on whether the slab's elements at the sections of its largest
    !> fibre stress and N/h resolve its bending (docs/theory.md section 13): their length
    !> along the slope a against pi / (6 lambda) of the stage's largest radius.
    pure function resolution_note(ex) result(text)
        type(body_extremes_t), intent(in) :: ex
        character(len=:), allocatable :: text
        character(len=*), parameter :: see = ', docs/tianshengqiao.md 11.5'
        character(len=300) :: line
        if (ex%resolution_limit <= 0.0_dp) then
            text = '  '//ex%body//' resolution: not judged (pi/lambda not known: no slab node'// &
                   ' on a support with a rockfill element beside it)'
            return
        end if
        if (max(ex%fibre_length, ex%membrane_length) <= ex%resolution_limit) then
            write (line, '(a,2(f7.3,a),f7.3,a)') ' resolution: resolved: a =', &
                ex%fibre_length, ' m (max fibre),', ex%membrane_length, &
                ' m (max N/h) <= pi/(6 lambda) =', ex%resolution_limit, &
                ' m, the slab element along the slope (docs/theory.md section 13)'
        else if (ex%fibre_length > ex%resolution_limit) then
            write (line, '(a,2(f7.3,a),f7.3,a)') ' resolution: not resolved: a =', &
                ex%fibre_length, ' m > pi/(6 lambda) =', ex%resolution_limit, &
                ' m at the max fibre section (max N/h:', ex%membrane_length, &
                ' m), fibre stresses not converged'//see
        else
            write (line, '(a,2(f7.3,a),f7.3,a)') ' resolution: max fibre resolved (a =', &
                ex%fibre_length, ' m); max N/h not resolved: a =', ex%membrane_length, &
                ' m > pi/(6 lambda) =', ex%resolution_limit, ' m'//see
        end if
        text = '  '//ex%body//trim(line)
    end function resolution_note

    function centroid_of(model, e) result(c)
        type(model_t), intent(in) :: model
        integer, intent(in) :: e
        real(dp) :: c(2)
        c = sum(model%mesh%x(:, model%mesh%conn(:, e)), dim=2)/4.0_dp
    end function centroid_of
end module cfrd_listing
