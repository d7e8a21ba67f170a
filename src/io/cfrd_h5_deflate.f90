!> The HDF5 library opened with libdeflate as its deflate filter (issue 21,
!> docs/performance.md (u)): h5_open is h5open_f followed by the registration of the
!> filter of cfrd_h5_deflate.c under HDF5's deflate id, so every file cfrd writes or reads
!> after it goes through libdeflate. The files stay standard (filter id 1, zlib streams):
!> any HDF5 reader inflates them with zlib. H5close forgets the filter, so every h5open_f
!> of cfrd goes through h5_open. If HDF5 refuses the registration, its own zlib filter
!> stays: the same values and format, the old speed (registered() tells).
module cfrd_h5_deflate
    use, intrinsic :: iso_c_binding, only: c_int, c_long
    use hdf5, only: h5open_f
    implicit none
    private

    public :: h5_open, registered, deflate_counts

    logical :: last_registered = .false.

    interface
        integer(c_int) function cfrd_deflate_register() bind(C, name='cfrd_deflate_register')
            import :: c_int
        end function cfrd_deflate_register

        subroutine cfrd_deflate_counts(deflated, inflated, failed) &
            bind(C, name='cfrd_deflate_counts')
            import :: c_long
            integer(c_long), intent(out) :: deflated, inflated, failed
        end subroutine cfrd_deflate_counts
    end interface

contains

    !> h5open_f, then libdeflate in the place of zlib's deflate filter; hdferr is
    !> h5open_f's (a refused registration leaves zlib's filter and is no error).
    subroutine h5_open(hdferr)
        integer, intent(out) :: hdferr
        call h5open_f(hdferr)
        if (hdferr < 0) return
        last_registered = cfrd_deflate_register() == 0
    end subroutine h5_open

    !> Whether the last h5_open put libdeflate's filter in place.
    logical function registered()
        registered = last_registered
    end function registered

    !> Chunks compressed and decompressed through libdeflate since the process started, and
    !> the filter's failures (each a chunk stored unfiltered or a read error).
    subroutine deflate_counts(deflated, inflated, failed)
        integer, intent(out) :: deflated, inflated, failed
        integer(c_long) :: d, i, f
        call cfrd_deflate_counts(d, i, f)
        deflated = int(d)
        inflated = int(i)
        failed = int(f)
    end subroutine deflate_counts

end module cfrd_h5_deflate
