!> cfrd --restart RESULTS.h5 [--from-stage K] [DECK] (docs/results.md, "Restart"): the
!> results file a run continues from, checked (a cfrd results file of layout 4 or later,
!> stage K completed in it), the model it continues (the stored deck, or DECK after
!> checking that it is the stored deck up to stage K), the stored stages read back, and
!> where the new result set goes.
module cfrd_restart
    use hdf5, only: hid_t, h5fopen_f, h5fclose_f, h5eset_auto_f, H5F_ACC_RDONLY_F
    use cfrd_h5_deflate, only: h5_open
    use cfrd_error, only: error_t, fatal_error, input_error
    use cfrd_strings, only: to_text
    use cfrd_model, only: model_t
    use cfrd_results, only: stage_result_t
    use cfrd_deck, only: read_deck
    use cfrd_model_compare, only: first_difference
    use cfrd_files, only: base_name
    use cfrd_h5_datasets, only: h5_state_t
    use cfrd_h5_read, only: text_attribute, int_attribute, read_text
    use cfrd_h5_state, only: read_stored_stage
    implicit none
    private

    public :: restart_t, open_restart, restart_model, restart_stem, read_restart_stage, &
              close_restart, restart_layout

    !> The first layout whose stages hold their restart state.
    integer, parameter :: restart_layout = 4

    !> A results file open to continue from.
    type :: restart_t
        character(len=:), allocatable :: path         !! RESULTS.h5 as given
        integer(hid_t) :: file_id = -1
        integer :: from_stage = 0                     !! K: the last stage taken from it
        integer :: completed = 0                      !! its stages_completed
        character(len=:), allocatable :: deck_text    !! /input/deck
        character(len=:), allocatable :: deck_file    !! the deck as its run named it
        character(len=:), allocatable :: deck_sha256, deck_path, run_id
        !> how it stores its values: a run that stores them alike copies the stored
        !> stages' groups instead of writing them again
        integer :: deflate = -1
        logical :: single = .false.
        logical :: full = .true.     !! --results full (files before it have everything)
    end type restart_t

contains

    !> Open `path` to continue from stage `from_stage` (0: its last completed stage). Input
    !> errors (exit 2): not an HDF5 file, not cfrd's, a layout before 4, no such stage.
    subroutine open_restart(path, from_stage, source, error)
        character(len=*), intent(in) :: path
        integer, intent(in) :: from_stage
        type(restart_t), intent(out) :: source
        type(error_t), allocatable, intent(out) :: error
        type(h5_state_t) :: st
        integer :: hdferr, layout
        source%path = path
        call h5_open(hdferr)
        call h5eset_auto_f(0, hdferr)
        call h5fopen_f(path, H5F_ACC_RDONLY_F, source%file_id, hdferr)
        if (hdferr < 0) then
            source%file_id = -1
            call fatal_error(error, path//': cannot restart from it: not a readable HDF5 '// &
                             'file', input_error)
            return
        end if
        if (text_attribute(source%file_id, 'program') /= 'cfrd') then
            call fatal_error(error, path//': cannot restart from it: not a cfrd results '// &
                             'file (no root attribute program = cfrd)', input_error)
            return
        end if
        layout = int_attribute(source%file_id, 'layout_version')
        if (layout < restart_layout) then
            call fatal_error(error, path//': cannot restart from it: results layout '// &
                             to_text(layout)//' keeps no restart state (layout '// &
                             to_text(restart_layout)//' and later do); run the deck again', &
                             input_error)
            return
        end if
        source%completed = int_attribute(source%file_id, 'stages_completed')
        source%from_stage = from_stage
        if (from_stage == 0) source%from_stage = source%completed
        if (source%from_stage < 1 .or. source%from_stage > source%completed) then
            call fatal_error(error, path//': cannot restart from stage '// &
                             to_text(source%from_stage)//': the file holds stages 1 to '// &
                             to_text(source%completed)//' (stages_completed = '// &
                             to_text(source%completed)//')', input_error)
            return
        end if
        source%deck_file = text_attribute(source%file_id, 'deck_file')
        source%deck_sha256 = text_attribute(source%file_id, 'deck_sha256')
        source%deck_path = text_attribute(source%file_id, 'deck_path')
        source%run_id = text_attribute(source%file_id, 'run_id')
        source%deflate = int_attribute(source%file_id, 'deflate_level')
        source%single = text_attribute(source%file_id, 'fields_precision') == 'float32'
        source%full = text_attribute(source%file_id, 'results') /= 'lean'
        call read_text(source%file_id, 'input/deck', source%deck_text, st)
        if (.not. st%ok) call fatal_error(error, path//': cannot restart from it: HDF5 '// &
                                          'failed at '//st%failed, input_error)
    end subroutine open_restart

    !> The model of the restart: the stored deck (`deck` = ''), or `deck` when it is the
    !> stored deck up to stage K (else an input error naming the first difference).
    subroutine restart_model(source, deck, model, error)
        type(restart_t), intent(in) :: source
        character(len=*), intent(in) :: deck
        type(model_t), intent(out) :: model
        type(error_t), allocatable, intent(out) :: error
        type(model_t) :: stored
        character(len=:), allocatable :: difference
        if (len(deck) == 0) then
            call read_deck(source%deck_file, model, error, source%deck_text)
            if (allocated(error)) error%message = 'the deck stored in '//source%path// &
                                                  ': '//error%message
            return
        end if
        call read_deck(deck, model, error)
        if (allocated(error)) return
        call read_deck(source%deck_file, stored, error, source%deck_text)
        if (allocated(error)) then
            error%message = 'the deck stored in '//source%path//': '//error%message
            return
        end if
        difference = first_difference(stored, model, source%from_stage)
        if (len(difference) > 0) call fatal_error(error, deck//': cannot continue '// &
            source%path//' after stage '//to_text(source%from_stage)//': the deck differs '// &
            'from its deck ('//source%deck_file//') up to that stage; first difference: '// &
            difference//' (here: '//deck//', there: the stored deck)', input_error)
    end subroutine restart_model

    !> Where a restart without a deck writes its results: the results file's name without
    !> .h5 (or .incomplete.h5), beside it or in `out_dir`.
    function restart_stem(source, out_dir) result(stem)
        type(restart_t), intent(in) :: source
        character(len=*), intent(in), optional :: out_dir
        character(len=:), allocatable :: stem
        integer :: n
        stem = source%path
        n = len(stem)
        if (n > 14) then
            if (stem(n - 13:) == '.incomplete.h5') stem = stem(:n - 14)
        end if
        n = len(stem)
        if (n > 3) then
            if (stem(n - 2:) == '.h5') stem = stem(:n - 3)
        end if
        if (present(out_dir)) stem = out_dir//'/'//base_name(stem)
    end function restart_stem

    !> Stage `number` as stored (for the stage driver).
    !> `light`: only what the stage's summary and CSV rows need (read_stored_stage).
    subroutine read_restart_stage(source, number, stage, light, error)
        type(restart_t), intent(in) :: source
        integer, intent(in) :: number
        type(stage_result_t), intent(out) :: stage
        logical, intent(in) :: light
        type(error_t), allocatable, intent(out) :: error
        call read_stored_stage(source%file_id, source%path, number, stage, error, light)
    end subroutine read_restart_stage

    subroutine close_restart(source)
        type(restart_t), intent(inout) :: source
        integer :: hdferr
        if (source%file_id < 0) return
        call h5fclose_f(source%file_id, hdferr)
        source%file_id = -1
    end subroutine close_restart
end module cfrd_restart
