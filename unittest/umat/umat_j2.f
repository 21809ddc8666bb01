c     J2 (von Mises) plasticity with linear isotropic hardening, radial
c     return, small strain, as an Abaqus UMAT, for the tests of
c     PERI-NOSPD's strain umat (the built-in "yield s hardening linear H"
c     law is the reference).
c     PROPS: E, nu, initial yield stress, hardening modulus H.
c     STATEV: 1-6 plastic strain (tensor components, 11 22 33 12 13 23),
c             7 equivalent plastic strain.
c     Too few PROPS or STATEV stop the run through STDB_ABQERR.
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
      dimension s(6), eps(6), ep(6), intv(1), realv(1)
      character*8 charv(1)
      if (nprops .lt. 4) then
        intv(1) = nprops
        call stdb_abqerr(-3, 'umat_j2 needs 4 PROPS, got %I',
     1                   intv, realv, charv)
        return
      end if
      if (nstatv .lt. 7) then
        intv(1) = nstatv
        call stdb_abqerr(-3, 'umat_j2 needs 7 STATEV, got %I',
     1                   intv, realv, charv)
        return
      end if
      e = props(1)
      xnu = props(2)
      sy0 = props(3)
      h = props(4)
      g = e/(2.d0*(1.d0+xnu))
      bk = e/(3.d0*(1.d0-2.d0*xnu))
c     full 6-component tensors (shear as tensor components)
      do i = 1, 6
        s(i) = 0.d0
        eps(i) = 0.d0
        ep(i) = statev(i)
      end do
      do i = 1, ntens
        if (i .le. 3) then
          eps(i) = stran(i) + dstran(i)
        else
          eps(i) = 0.5d0*(stran(i) + dstran(i))
        end if
      end do
c     trial stress from the elastic strain eps - ep
      tr = eps(1)+eps(2)+eps(3) - ep(1)-ep(2)-ep(3)
      do i = 1, 3
        s(i) = 2.d0*g*(eps(i)-ep(i) - tr/3.d0)
      end do
      do i = 4, 6
        s(i) = 2.d0*g*(eps(i)-ep(i))
      end do
      q = sqrt(1.5d0*(s(1)**2+s(2)**2+s(3)**2
     1        + 2.d0*(s(4)**2+s(5)**2+s(6)**2)))
      a = statev(7)
      f = q - (sy0 + h*a)
      if (f .gt. 0.d0) then
        dg = f/(3.d0*g + h)
        do i = 1, 6
          ep(i) = ep(i) + 1.5d0*dg*s(i)/q
          s(i) = s(i)*(1.d0 - 3.d0*g*dg/q)
        end do
        a = a + dg
        spd = spd + dg*(sy0 + h*a)
      end if
      p = bk*tr
      do i = 1, ntens
        if (i .le. 3) then
          stress(i) = s(i) + p
        else
          stress(i) = s(i)
        end if
      end do
      do i = 1, 6
        statev(i) = ep(i)
      end do
      statev(7) = a
c     elastic energy of eps - ep
      sse = 0.5d0*bk*tr*tr
      do i = 1, 3
        sse = sse + g*(eps(i)-ep(i)-tr/3.d0)**2
      end do
      do i = 4, 6
        sse = sse + 2.d0*g*(eps(i)-ep(i))**2
      end do
      return
      end
