!> Datasets stored once (issue 21, docs/results.md "What is written"): a stage dataset whose
!> values are bit for bit those of a dataset already in the file is written as an HDF5 hard
!> link to it, a second name of the same object. Every HDF5 reader (h5py, h5dump, ParaView)
!> reads the values through either name without knowing; the file keeps the data once.
!> Used for what does not change from stage to stage (the slab's and the interfaces'
!> geometry; the Gauss-point fields, stress levels and reactions at a RESET stage, which
!> changes no stress).
module cfrd_h5_links
    use, intrinsic :: iso_fortran_env, only: int64
    use hdf5, only: hid_t, h5lcreate_hard_f
    use cfrd_kinds, only: dp
    use cfrd_h5_datasets, only: h5_state_t, fail, dataset_real1, dataset_real2, dataset_real3
    implicit none
    private

    public :: kept_t, real1_once, real2_once, real3_once

    !> The last values written under one key (such as 'slab/x') and where they are.
    type :: kept_t
        character(len=:), allocatable :: key
        character(len=:), allocatable :: path     !! absolute path of the dataset
        integer :: dims(3) = 0
        real(dp), allocatable :: values(:)
    end type kept_t

contains

    !> Whether a and b hold the same bits (so -0 differs from +0, as in the file).
    pure logical function same_bits(a, b)
        real(dp), intent(in) :: a(:), b(:)
        same_bits = size(a) == size(b)
        if (same_bits) same_bits = all(transfer(a, 0_int64, size(a)) == &
                                       transfer(b, 0_int64, size(b)))
    end function same_bits

    !> The index of the entry of `kept` for `key` (default `name`), appended when there is
    !> none.
    function kept_index(kept, name, key) result(k)
        type(kept_t), allocatable, intent(inout) :: kept(:)
        character(len=*), intent(in) :: name
        character(len=*), intent(in), optional :: key
        integer :: k
        type(kept_t), allocatable :: grown(:)
        character(len=:), allocatable :: id
        id = name
        if (present(key)) id = key
        if (.not. allocated(kept)) allocate (kept(0))
        do k = 1, size(kept)
            if (kept(k)%key == id) return
        end do
        allocate (grown(size(kept) + 1))
        grown(1:size(kept)) = kept
        grown(size(grown))%key = id
        call move_alloc(grown, kept)
        k = size(kept)
    end function kept_index

    !> `name` in group `loc` (absolute path `group_path`) as a hard link to `kept`'s dataset
    !> when `values` (shape `dims`) are its values to the bit (`linked`); else kept, for
    !> the caller to write.
    subroutine try_link(kept, loc, group_path, name, values, dims, st, linked)
        type(kept_t), intent(inout) :: kept
        integer(hid_t), intent(in) :: loc
        character(len=*), intent(in) :: group_path, name
        real(dp), intent(in) :: values(:)
        integer, intent(in) :: dims(3)
        type(h5_state_t), intent(inout) :: st
        logical, intent(out) :: linked
        integer :: hdferr
        linked = .false.
        if (.not. st%ok) return
        if (allocated(kept%path)) then
            if (all(kept%dims == dims)) linked = same_bits(kept%values, values)
        end if
        if (linked) then
            call h5lcreate_hard_f(loc, kept%path, loc, name, hdferr)
            if (hdferr < 0) call fail(st, 'link '//name//' to '//kept%path)
        else
            kept%path = group_path//'/'//name
            kept%dims = dims
            kept%values = values
        end if
    end subroutine try_link

    !> A (n,) dataset `name` of group `loc` (absolute path `group_path`), stored once while
    !> its values stay the same (module comment) when `link` (a lean file), else written.
    !> `key` (default `name`) names it among the kept datasets.
    subroutine real1_once(kept, link, loc, group_path, name, values, units, components, st, &
                          key)
        type(kept_t), allocatable, intent(inout) :: kept(:)
        logical, intent(in) :: link
        character(len=*), intent(in) :: group_path, name, units, components
        integer(hid_t), intent(in) :: loc
        real(dp), intent(in) :: values(:)
        type(h5_state_t), intent(inout) :: st
        character(len=*), intent(in), optional :: key
        logical :: done
        integer :: k
        done = .false.
        if (link) then
            k = kept_index(kept, name, key)    ! (it may grow `kept`: first, then kept(k))
            call try_link(kept(k), loc, group_path, name, values, [size(values), 1, 1], st, &
                          done)
        end if
        if (.not. done) call dataset_real1(loc, name, values, units, components, st)
    end subroutine real1_once

    !> The same for a (m, n) dataset.
    subroutine real2_once(kept, link, loc, group_path, name, values, units, components, st, &
                          key)
        type(kept_t), allocatable, intent(inout) :: kept(:)
        logical, intent(in) :: link
        character(len=*), intent(in) :: group_path, name, units, components
        integer(hid_t), intent(in) :: loc
        real(dp), intent(in) :: values(:, :)
        type(h5_state_t), intent(inout) :: st
        character(len=*), intent(in), optional :: key
        logical :: done
        integer :: k
        done = .false.
        if (link) then
            k = kept_index(kept, name, key)
            call try_link(kept(k), loc, group_path, name, pack(values, .true.), &
                          [shape(values), 1], st, done)
        end if
        if (.not. done) call dataset_real2(loc, name, values, units, components, st)
    end subroutine real2_once

    !> The same for a (l, m, n) dataset.
    subroutine real3_once(kept, link, loc, group_path, name, values, units, components, st)
        type(kept_t), allocatable, intent(inout) :: kept(:)
        logical, intent(in) :: link
        character(len=*), intent(in) :: group_path, name, units, components
        integer(hid_t), intent(in) :: loc
        real(dp), intent(in) :: values(:, :, :)
        type(h5_state_t), intent(inout) :: st
        logical :: done
        integer :: k
        done = .false.
        if (link) then
            k = kept_index(kept, name)
            call try_link(kept(k), loc, group_path, name, pack(values, .true.), &
                          shape(values), st, done)
        end if
        if (.not. done) call dataset_real3(loc, name, values, units, components, st)
    end subroutine real3_once
end module cfrd_h5_links
