program cfrd_main
    implicit none
    print '(a)', 'cfrd: not yet'
end program cfrd_main
