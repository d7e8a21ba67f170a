!> Reading an HDF5 results file back (cfrd --check, cfrd --restart): attributes of any
!> object, and datasets of doubles or integers of any shape the file has, each read checked.
!> As in the writers (cfrd_h5_datasets), the first failure is carried in `h5_state_t` and later
!> reads are skipped; the caller turns it into an error naming the object.
module cfrd_h5_read
    use hdf5, only: hid_t, size_t, hsize_t, h5aexists_f, h5aopen_f, h5aread_f, h5aclose_f, &
                    h5aget_type_f, h5tget_size_f, h5tclose_f, h5tcopy_f, h5tset_size_f, &
                    H5T_NATIVE_INTEGER, H5T_NATIVE_CHARACTER, H5T_NATIVE_DOUBLE, &
                    h5dopen_f, h5dread_f, h5dclose_f, h5dget_space_f, h5sclose_f, &
                    h5sget_simple_extent_ndims_f, h5sget_simple_extent_dims_f, h5lexists_f, &
                    h5dget_type_f
    use cfrd_kinds, only: dp
    use cfrd_h5_datasets, only: h5_state_t, fail
    implicit none
    private

    public :: text_attribute, int_attribute, real_attribute, has_object
    public :: read_reals, read_ints, read_text

contains

    !> A string attribute of an object ('' when absent), trailing blanks removed.
    function text_attribute(file_id, name) result(text)
        integer(hid_t), intent(in) :: file_id
        character(len=*), intent(in) :: name
        character(len=:), allocatable :: text
        integer(hid_t) :: attr_id, file_type, memory_type
        integer(size_t) :: width
        logical :: exists
        integer :: hdferr
        text = ''
        call h5aexists_f(file_id, name, exists, hdferr)
        if (hdferr < 0 .or. .not. exists) return
        call h5aopen_f(file_id, name, attr_id, hdferr)
        if (hdferr < 0) return
        call h5aget_type_f(attr_id, file_type, hdferr)
        call h5tget_size_f(file_type, width, hdferr)
        call h5tclose_f(file_type, hdferr)
        if (hdferr >= 0 .and. width > 0) then
            deallocate (text)
            allocate (character(len=int(width)) :: text)
            call h5tcopy_f(H5T_NATIVE_CHARACTER, memory_type, hdferr)
            call h5tset_size_f(memory_type, width, hdferr)
            call h5aread_f(attr_id, memory_type, text, [1_hsize_t], hdferr)
            call h5tclose_f(memory_type, hdferr)
            if (hdferr < 0) then
                text = ''
            else
                text = trim(text)
            end if
        end if
        call h5aclose_f(attr_id, hdferr)
    end function text_attribute

    !> An integer attribute of an object (-1 when absent), read through the real one
    !> (HDF5 converts; exact for 32-bit integers).
    integer function int_attribute(loc, name) result(value)
        integer(hid_t), intent(in) :: loc
        character(len=*), intent(in) :: name
        value = nint(real_attribute(loc, name, -1.0_dp))
    end function int_attribute

    !> A real attribute of an object (`default` when absent).
    real(dp) function real_attribute(loc, name, default) result(value)
        integer(hid_t), intent(in) :: loc
        character(len=*), intent(in) :: name
        real(dp), intent(in) :: default
        integer(hid_t) :: attr_id
        logical :: exists
        integer :: hdferr
        real(dp) :: buffer(1)
        value = default
        call h5aexists_f(loc, name, exists, hdferr)
        if (hdferr < 0 .or. .not. exists) return
        call h5aopen_f(loc, name, attr_id, hdferr)
        if (hdferr < 0) return
        call h5aread_f(attr_id, H5T_NATIVE_DOUBLE, buffer, [1_hsize_t], hdferr)
        if (hdferr >= 0) value = buffer(1)
        call h5aclose_f(attr_id, hdferr)
    end function real_attribute

    !> Whether `loc` has a link `name` (a group or a dataset).
    logical function has_object(loc, name)
        integer(hid_t), intent(in) :: loc
        character(len=*), intent(in) :: name
        integer :: hdferr
        call h5lexists_f(loc, name, has_object, hdferr)
        if (hdferr < 0) has_object = .false.
    end function has_object

    !> Open dataset `name` of `loc` and give its shape, which must have `rank` dimensions.
    subroutine open_dataset(loc, name, rank, dset_id, dims, st)
        integer(hid_t), intent(in) :: loc
        character(len=*), intent(in) :: name
        integer, intent(in) :: rank
        integer(hid_t), intent(out) :: dset_id
        integer(hsize_t), intent(out) :: dims(rank)
        type(h5_state_t), intent(inout) :: st
        integer(hid_t) :: space_id
        integer(hsize_t) :: maxdims(rank)
        integer :: hdferr, ndims
        dset_id = -1
        dims = 0
        if (.not. st%ok) return
        call h5dopen_f(loc, name, dset_id, hdferr)
        if (hdferr < 0) then
            dset_id = -1
            call fail(st, 'dataset '//name)
            return
        end if
        call h5dget_space_f(dset_id, space_id, hdferr)
        if (hdferr >= 0) call h5sget_simple_extent_ndims_f(space_id, ndims, hdferr)
        if (hdferr >= 0 .and. ndims == rank) &
            call h5sget_simple_extent_dims_f(space_id, dims, maxdims, hdferr)
        if (hdferr < 0 .or. ndims /= rank) call fail(st, 'the shape of dataset '//name)
        call h5sclose_f(space_id, hdferr)
    end subroutine open_dataset

    subroutine close_dataset(dset_id, name, hdferr, st)
        integer(hid_t), intent(in) :: dset_id
        character(len=*), intent(in) :: name
        integer, intent(in) :: hdferr
        type(h5_state_t), intent(inout) :: st
        integer :: err
        if (hdferr < 0) call fail(st, 'reading dataset '//name)
        if (dset_id >= 0) call h5dclose_f(dset_id, err)
    end subroutine close_dataset

    !> A dataset of `values`' rank (1 to 3) read as doubles, whatever the file stores.
    subroutine read_reals(loc, name, values, st)
        integer(hid_t), intent(in) :: loc
        character(len=*), intent(in) :: name
        real(dp), allocatable, intent(out) :: values(..)
        type(h5_state_t), intent(inout) :: st
        integer(hid_t) :: dset_id
        integer(hsize_t) :: dims(3)
        integer :: hdferr
        dims = 1
        call open_dataset(loc, name, rank(values), dset_id, dims(1:rank(values)), st)
        hdferr = 0
        select rank (values)
        rank (1)
            allocate (values(dims(1)))
            if (st%ok) call h5dread_f(dset_id, H5T_NATIVE_DOUBLE, values, dims(1:1), hdferr)
        rank (2)
            allocate (values(dims(1), dims(2)))
            if (st%ok) call h5dread_f(dset_id, H5T_NATIVE_DOUBLE, values, dims(1:2), hdferr)
        rank (3)
            allocate (values(dims(1), dims(2), dims(3)))
            if (st%ok) call h5dread_f(dset_id, H5T_NATIVE_DOUBLE, values, dims, hdferr)
        end select
        call close_dataset(dset_id, name, hdferr, st)
    end subroutine read_reals

    !> A dataset of integers of rank 1.
    subroutine read_ints(loc, name, values, st)
        integer(hid_t), intent(in) :: loc
        character(len=*), intent(in) :: name
        integer, allocatable, intent(out) :: values(:)
        type(h5_state_t), intent(inout) :: st
        integer(hid_t) :: dset_id
        integer(hsize_t) :: dims(1)
        integer :: hdferr
        call open_dataset(loc, name, 1, dset_id, dims, st)
        allocate (values(dims(1)))
        hdferr = 0
        if (st%ok) call h5dread_f(dset_id, H5T_NATIVE_INTEGER, values, dims, hdferr)
        call close_dataset(dset_id, name, hdferr, st)
    end subroutine read_ints

    !> A scalar string dataset (the deck, /input/deck), as written (its length).
    subroutine read_text(loc, name, text, st)
        integer(hid_t), intent(in) :: loc
        character(len=*), intent(in) :: name
        character(len=:), allocatable, intent(out) :: text
        type(h5_state_t), intent(inout) :: st
        integer(hid_t) :: dset_id, file_type, memory_type
        integer(size_t) :: width
        integer(hsize_t) :: dims(0)
        integer :: hdferr, err
        text = ''
        if (.not. st%ok) return
        call h5dopen_f(loc, name, dset_id, hdferr)
        if (hdferr < 0) then
            call fail(st, 'dataset '//name)
            return
        end if
        call h5dget_type_f(dset_id, file_type, hdferr)
        if (hdferr >= 0) call h5tget_size_f(file_type, width, hdferr)
        if (hdferr >= 0) then
            call h5tclose_f(file_type, err)
            deallocate (text)
            allocate (character(len=int(width)) :: text)
            call h5tcopy_f(H5T_NATIVE_CHARACTER, memory_type, hdferr)
            if (hdferr >= 0) call h5tset_size_f(memory_type, width, hdferr)
            if (hdferr >= 0) call h5dread_f(dset_id, memory_type, text, dims, hdferr)
            call h5tclose_f(memory_type, err)
        end if
        call close_dataset(dset_id, name, hdferr, st)
    end subroutine read_text
end module cfrd_h5_read
