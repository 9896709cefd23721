! Phantom's get_kernel(q2, q, wkern, grkern) timed as Phantom's density and
! force loops call it: one call per neighbour, from another module (no
! inlining across it), q spread over [0, radkern) by the golden ratio.
! Built once against Phantom's stock `module kernel` and once against
! mollify's (`mollify-gen emit --target phantom`), with Phantom's flags
! (bench/phantom_kernel_bench.sh). Prints the least ns a call of RUNS runs
! of SWEEPS sweeps over N points, and cnormk times the sums of wkern and
! grkern over one sweep (ns_called, sum_w, sum_dw: bench/peers/common.sh's
! keys), so that the two modules' values can be compared
! (Phantom's w and mollify's differ by their split into cnormk w, and
! Phantom's physcon pi is 3.1415926536, 3.2e-12 above pi).
program phantom_get_kernel
 use kernel, only: get_kernel, radkern, cnormk
 implicit none
 integer, parameter :: n = 4096, runs = 7
 real :: q(n), q2(n), w, g, sw, sg, sw1, sg1, best, elapsed
 integer :: i, it, run, sweeps, stat
 integer(kind=8) :: t0, t1, rate
 character(len=32) :: arg

 sweeps = 20000
 if (command_argument_count() >= 1) then
  call get_command_argument(1, arg)
  read(arg, *, iostat=stat) sweeps
  if (stat /= 0 .or. sweeps < 1) then
   print '(a)', 'phantom_get_kernel: SWEEPS must be a positive integer, not "' // trim(arg) // '"'
   stop 2
  end if
 end if
 do i = 1, n
  q(i) = radkern * mod(i * 0.6180339887498949d0, 1.d0)
  q2(i) = q(i)**2
 end do
 ! one sweep's sums, for the values (a long sum's own rounding differs with the order of its terms)
 sw1 = 0.
 sg1 = 0.
 do i = 1, n
  call get_kernel(q2(i), q(i), w, g)
  sw1 = sw1 + w
  sg1 = sg1 + g
 end do
 best = huge(best)
 do run = 1, runs
  sw = 0.
  sg = 0.
  call system_clock(t0, rate)
  do it = 1, sweeps
   do i = 1, n
    call get_kernel(q2(i), q(i), w, g)
    sw = sw + w
    sg = sg + g
   end do
  end do
  call system_clock(t1)
  elapsed = real(t1 - t0) / real(rate)
  best = min(best, elapsed / (real(sweeps) * real(n)) * 1.e9)
 end do
 if (.not. (abs(sw + sg) >= 0.)) stop 1  ! the timed sums are used (a NaN stops it)
 print '(a,f8.3,a,es24.16,a,es24.16)', 'ns_called ', best, ' sum_w ', cnormk * sw1, &
  ' sum_dw ', cnormk * sg1
end program phantom_get_kernel
