c     Isotropic linear elasticity as an Abaqus UMAT, for the tests of
c     PERI-NOSPD's strain umat (the built-in strain small law is the
c     reference).  PROPS(1) = E, PROPS(2) = nu; PROPS(3) /= 0 makes it
c     return a NaN stress (the bad-output check); PROPS(4) = n makes it
c     write STATEV(1..n) whatever NSTATV is (the overflow check),
c     adding I to STATEV(I) instead when PROPS(5) /= 0; PROPS(6) /= 0
c     stores TIME(1), TIME(2), DTIME in STATEV(1..3); PROPS(7) /= 0
c     stores NPT and NOEL in STATEV(4..5).  Works for NTENS = 6
c     (3D) and NTENS = 4 (plane strain).  SSE by the trapezoidal rule,
c     exact for a linear law.
      subroutine umat(stress,statev,ddsdde,sse,spd,scd,
     1 rpl,ddsddt,drplde,drpldt,
     2 stran,dstran,time,dtime,temp,dtemp,predef,dpred,cmname,
     3 ndi,nshr,ntens,nstatv,props,nprops,coords,drot,pnewdt,
     4 celent,dfgrd0,dfgrd1,noel,npt,layer,kspt,kstep,kinc)
      include 'aba_param.inc'
      character*80 cmname
      dimension stress(ntens),statev(*),
     1 ddsdde(ntens,ntens),ddsddt(ntens),drplde(ntens),
     2 stran(ntens),dstran(ntens),time(2),predef(1),dpred(1),
     3 props(nprops),coords(3),drot(3,3),dfgrd0(3,3),dfgrd1(3,3)
      dimension sold(6)
      e = props(1)
      xnu = props(2)
      xlam = e*xnu/((1.d0+xnu)*(1.d0-2.d0*xnu))
      xmu = e/(2.d0*(1.d0+xnu))
      do i = 1, ntens
        do j = 1, ntens
          ddsdde(i,j) = 0.d0
        end do
        sold(i) = stress(i)
      end do
      do i = 1, ndi
        do j = 1, ndi
          ddsdde(i,j) = xlam
        end do
        ddsdde(i,i) = xlam + 2.d0*xmu
      end do
      do i = ndi+1, ntens
        ddsdde(i,i) = xmu
      end do
      do i = 1, ntens
        do j = 1, ntens
          stress(i) = stress(i) + ddsdde(i,j)*dstran(j)
        end do
      end do
      do i = 1, ntens
        sse = sse + 0.5d0*(sold(i)+stress(i))*dstran(i)
      end do
      if (nprops .ge. 3) then
        if (props(3) .ne. 0.d0) then
          zero = 0.d0
          stress(1) = zero/zero
        end if
      end if
      if (nprops .ge. 6) then
        if (props(6) .ne. 0.d0) then
          statev(1) = time(1)
          statev(2) = time(2)
          statev(3) = dtime
        end if
      end if
      if (nprops .ge. 7) then
        if (props(7) .ne. 0.d0) then
          statev(4) = dble(npt)
          statev(5) = dble(noel)
        end if
      end if
      if (nprops .ge. 4) then
        iacc = 0
        if (nprops .ge. 5) then
          if (props(5) .ne. 0.d0) iacc = 1
        end if
        do i = 1, int(props(4))
          if (iacc .eq. 1) then
            statev(i) = statev(i) + dble(i)
          else
            statev(i) = 1.d0
          end if
        end do
      end if
      return
      end
