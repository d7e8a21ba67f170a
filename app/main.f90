program cfrd_main
end program cfrd_main
