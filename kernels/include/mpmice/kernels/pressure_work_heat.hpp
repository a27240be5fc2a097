#pragma once
/// \file pressure_work_heat.hpp
/// \brief Total-energy consistency of the pressure work (an addition to
///        mpmice-algorithm.md, docs/design.md "Energy of the pressure work"): after the
///        exchange (E31), the heat that makes each cell's pressure work the flux form
///        -sum_faces p^f Phi^f, so that the work telescopes over the grid.
///
/// The internal-energy form charges the fluids p^{n+1}_c times their volume change
/// (E23), while the pressure force gives the materials the kinetic energy of the
/// face-pressure kick (E22) less what the exchange removes (E31). Their sum is not
/// the divergence of a flux: where the pressure jumps between cells (gas trapped next
/// to a burning solid, held to it by the stiff drag, leaking out at the face velocity
/// (E18)), the gas pays its expansion work at its own cell's pressure and the kinetic
/// energy of that leak is never resolved by cell velocities; the work is lost instead of
/// heating the gas, as a throttled gas is heated by its friction. This kernel returns
/// the difference, per cell, as heat.
#include <mpmice/kernels/loops.hpp>
#include <mpmice/kernels/materials.hpp>

namespace mpmice {

/// Inputs of `pressure_work_heat` (all from the current step).
struct PressureWorkInputs {
  Kokkos::Array<ConstField3, 3> press_face;  ///< p^f (E21) on the faces of the cells
  Kokkos::Array<ConstField3, 3> face_flux;   ///< Phi^f: the fluids' volume flux (face_fluxes)
  Kokkos::Array<ConstField3, 3> solid_face_flux;  ///< Phi_s^f: the deforming solids' volume flux
  ConstField4 vol_frac;                      ///< theta_r (E16)
  ConstField4 work;                          ///< the fluids' energy sources W_r (E23)
  ConstField4 kappa;                         ///< kappa_r (E16), one layer of ghosts
  ConstField3 sum_kappa;                     ///< SK (E16), one layer of ghosts
  ConstField4 rho;                           ///< rho_r^n, for the gravity part of Q_r
  ConstField4 mass_L;                        ///< mL_r (E29, E30)
  ConstVectorField4 mom_L;                   ///< PL_r (E27-E30), including Q_r
  ConstVectorField4 mom_source;              ///< Q_r (E22)
  ConstVectorField4 vel_me;                  ///< u_r after the exchange (E31)
};

namespace detail {

// pressure_work_heat() for N materials, with or without a rigid one. The material
// kinds enter as factors 1 or 0 (exact for finite terms) instead of branches, so the
// loop over cells vectorises.
template <int N, bool HasRigid>
double pressure_work_heat_n(const IndexBox& cells, const Kokkos::Array<double, 3> h, double dt,
                            const Kokkos::Array<double, 3> gravity, const MaterialTable& mats,
                            const PressureWorkInputs& in, const Field4& temp_me, const Field4& temp_rate) {
  const double hx = h[0], hy = h[1], hz = h[2];
  const double V = hx * hy * hz;
  const PressureWorkInputs f = in;
  Kokkos::Array<double, N> ice, rigid, cv;
  for (int r = 0; r < N; ++r) {
    ice[r] = mats.is_ice(r) ? 1.0 : 0.0;
    rigid[r] = mats.is_rigid(r) ? 1.0 : 0.0;
    cv[r] = mats.eos[r].cv;
  }
  return reduce_over_index<Reduction::sum, Rows::longest>(
      "mpmice::pressure_work_heat", cells, KOKKOS_LAMBDA(long i, long j, long k) {
        // A rigid body's prescribed motion works from outside on its cells and, through
        // their faces, on the cells next to them: no balance there.
        double rigid_nearby = 0;  // the largest rigid volume fraction here and next door
        if (HasRigid) {
          unrolled_for<N>([&](int r) {
            double theta = f.vol_frac(r, i, j, k);
            unrolled_for<3>([&](int d) {
              const double lo = f.vol_frac(r, i - (d == 0), j - (d == 1), k - (d == 2));
              const double hi = f.vol_frac(r, i + (d == 0), j + (d == 1), k + (d == 2));
              theta = lo > theta ? lo : theta;
              theta = hi > theta ? hi : theta;
            });
            theta *= rigid[r];
            rigid_nearby = theta > rigid_nearby ? theta : rigid_nearby;
          });
        }
        const bool near_rigid = rigid_nearby > 1e-6;
        // Flux form: -sum over the six faces of (outward sign) p^f Phi^f.
        double flux_work = 0;
        unrolled_for<3>([&](int d) {
          const long hi[3] = {i + (d == 0), j + (d == 1), k + (d == 2)};
          flux_work -= f.press_face[d](hi[0], hi[1], hi[2]) * f.face_flux[d](hi[0], hi[1], hi[2]) -
                       f.press_face[d](i, j, k) * f.face_flux[d](i, j, k);
        });
        // The fluids' share of a volume change in cell (a, b, c): sum_ICE theta kappa / SK.
        auto fluid_share = [&](long a, long b, long c) {
          double theta_kappa = 0;
          unrolled_for<N>([&](int r) {
            const double theta = f.vol_frac(r, a, b, c);
            theta_kappa += theta > 1e-6 ? ice[r] * (theta * f.kappa(r, a, b, c)) : 0.0;
          });
          const double sum_kappa = f.sum_kappa(a, b, c);  // 0 in an extra cell past a wall
          return sum_kappa > 0.0 ? theta_kappa / sum_kappa : 0.0;
        };
        // The solids' push on the fluids in flux form: their volume flux through each
        // face at the face pressure, times the fluids' share (the mean of the face's two
        // cells). It telescopes: volume the solids carry from one cell to the next moves
        // energy between those cells' fluids, and none is made or lost over the grid.
        const double share = fluid_share(i, j, k);
        double solid_push = 0;
        unrolled_for<3>([&](int d) {
          const long hi[3] = {i + (d == 0), j + (d == 1), k + (d == 2)};
          const long lo[3] = {i - (d == 0), j - (d == 1), k - (d == 2)};
          const double share_lo = 0.5 * (share + fluid_share(lo[0], lo[1], lo[2]));
          const double share_hi = 0.5 * (share + fluid_share(hi[0], hi[1], hi[2]));
          solid_push += share_lo * f.press_face[d](i, j, k) * f.solid_face_flux[d](i, j, k) -
                        share_hi * f.press_face[d](hi[0], hi[1], hi[2]) * f.solid_face_flux[d](hi[0], hi[1], hi[2]);
        });
        // What (E23) charged: the sum of the fluids' energy sources (its mass-exchange
        // part sums to zero in a cell).
        double charged = 0;
        unrolled_for<N>([&](int r) { charged += ice[r] * f.work(r, i, j, k); });
        // Kinetic energy from the pressure kick (E22) and the exchange, every
        // non-rigid material's: the fluids pay for the solids' kick too.
        double kinetic = 0, thermal = 0;
        unrolled_for<N>([&](int r) {
          const double m = f.mass_L(r, i, j, k);
          const double weight = ice[r] * (f.rho(r, i, j, k) * V * dt);
          double after = 0, before = 0;
          unrolled_for<3>([&](int d) {
            const double u = f.vel_me[d](r, i, j, k);
            const double kick = (1.0 - rigid[r]) * (f.mom_source[d](r, i, j, k) - weight * gravity[d]);
            const double p0 = f.mom_L[d](r, i, j, k) - kick;
            after += u * u;
            before += p0 * p0;
          });
          kinetic += 0.5 * m * after - 0.5 * before / m;
          thermal += (1.0 - rigid[r]) * (m * cv[r] * temp_me(r, i, j, k));
        });
        // At most half the cell's thermal energy leaves in one step (a cell of trace
        // materials next to a large pressure jump); the rest is not put back.
        double heat = flux_work + solid_push - charged - kinetic;
        heat = heat < -0.5 * thermal ? -0.5 * thermal : heat;
        heat = near_rigid ? 0.0 : heat;
        const double scale = heat / thermal;
        unrolled_for<N>([&](int r) {
          const double dtemp = near_rigid ? 0.0 : (1.0 - rigid[r]) * (scale * temp_me(r, i, j, k));
          temp_me(r, i, j, k) += dtemp;
          temp_rate(r, i, j, k) += dtemp / dt;
        });
        return heat;
      });
}

}  // namespace detail

/// Over `cells`, the heat
///   heat_c = - sum_faces (outward) p^f Phi^f          the fluids' work in flux form
///            - sum_faces (outward) s^f p^f Phi_s^f     the solids' push on the fluids
///            - sum_ICE W_r                            what (E23) and mass_exchange_work charged
///            - sum_r [mL_r |u_r^ME|^2 - |PL_r - Q_r|^2 / mL_r] / 2
///                                                     kinetic energy from the kick and exchange
/// with Phi^f the fluids' volume flux through a face over the step (`face_fluxes`: the
/// slabs of theta that Adv[theta] of (E20) moves, summed over the ICE materials), Phi_s^f
/// the same for the deforming solids, s^f the fluids' share sum_ICE theta kappa / SK
/// averaged over the face's two cells, and Q_r the pressure part of the kick (E22) of a
/// non-rigid material (the solids' included: the fluids pay for the kinetic energy they
/// give the solids, which the particles receive with it, docs/design.md). Over a closed
/// box the first two terms sum to zero: the fluids' pressure work becomes exactly the
/// kinetic energy it makes. Cells holding a rigid material (theta > 1e-6),
/// and their face neighbours, are left alone: a prescribed motion works from outside.
/// heat_c goes to the non-rigid materials in proportion to m c_v T (one relative
/// temperature change, so a trace material takes a trace), at most -1/2 of sum m c_v T
/// (every temperature stays positive); `temp_me` and `temp_rate` (Tdot, read by E32)
/// change by it. Returns the sum of heat_c over `cells`, J.
inline double pressure_work_heat(const IndexBox& cells, const Kokkos::Array<double, 3> h, double dt,
                                 const Kokkos::Array<double, 3> gravity, const MaterialTable& mats,
                                 const PressureWorkInputs& in, const Field4& temp_me, const Field4& temp_rate) {
  bool has_rigid = false;
  for (int r = 0; r < mats.count; ++r) has_rigid = has_rigid || mats.is_rigid(r);
  double total = 0;
  with_material_count(mats.count, [&](auto n) {
    constexpr int N = decltype(n)::value;
    with_flag(has_rigid, [&](auto rigid) {
      total = detail::pressure_work_heat_n<N, decltype(rigid)::value>(cells, h, dt, gravity, mats, in, temp_me,
                                                                      temp_rate);
    });
  });
  return total;
}

#ifdef MPMICE_KERNEL_INSTANCES
// Compiled once for the project's own programs, in kernels/instances/ (g2p.hpp says why).
namespace detail {
#define MPMICE_PRESSURE_WORK_HEAT_N(N, HasRigid)                                                           \
  double pressure_work_heat_n<N, HasRigid>(const IndexBox&, const Kokkos::Array<double, 3>, double,         \
                                           const Kokkos::Array<double, 3>, const MaterialTable&,           \
                                           const PressureWorkInputs&, const Field4&, const Field4&)
MPMICE_EACH_COUNT_AND_FLAG(extern template, MPMICE_PRESSURE_WORK_HEAT_N)
}  // namespace detail
#endif

}  // namespace mpmice
