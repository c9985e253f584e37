"""What the report says per kind: the checks' value and allowable fields, the assumptions, the method (key
equations with the design's values substituted, each with its spec or paper reference) and the references in
full (copied from the References of docs/spec/<kind>.md)."""
from __future__ import annotations

import math

CHECKS = {
    # (kind, check): (value field, allowable field, what is checked)
    ("pins", "self_locking"): ("efficiency", None, "not self-locking (efficiency > 0)"),
    ("pins", "rolling"): (None, None, "the pins' bushings roll (f·R_b ≥ f_c·r + f_k)"),
    ("pins", "contact_stress"): ("contact_stress_max_MPa", None, "Hertz contact stress ≤ allowable"),
    ("zstk", "sigma"): ("sigma_max_MPa", "allowable_stress_MPa", "Hertz stress σ_max ≤ [σ_H] (eqs. (1)-(2))"),
    ("zstk", "closure"): ("N", "N_admissible_max", "the chain closes (N ≤ N_admissible_max)"),
    ("zstk", "clearance"): ("clearance_mm", None, "clearance keeps the rollers loaded"),
    ("rows", "bore"): (None, None, "the sun's bore stays inside its root and torsion diameters"),
    ("rows", "rim"): (None, None, "the sun's rim under the roots is at least 2.7 m thick"),
    ("rows", "bridge_fit"): ("bridge_max_mm", None, "every span's bridge fits between the planets"),
}

ASSUMPTIONS = {
    "pins": ["Rigid satellite and pins below the contact level; the contact level adds Hertz compliance "
             "(pins.md §5).",
             "Friction: Coulomb sliding at fixed pins (f), rolling resistance f_c·r + f_k at rotating pins "
             "(pins.md §4.5-4.6); the friction model is named in the results (friction_model).",
             "Not modelled: lubrication film, thermal effects, bearing losses other than the pins' contacts, "
             "manufacturing errors beyond the stated profile modifications."],
    "zstk": ["Closed chain of rollers between two eccentric raceways (Merko et al.); Hertz line contact "
             "(zstk.md §2).",
             "Load distribution from the rollers' elastic approach (Palmgren / ISO/TS 16281 stiffness, zstk.md §5); "
             "no friction in the load distribution.",
             "Not modelled: roller skew, edge stress (profiled rollers), dynamic loads, fatigue life."],
    "rows": ["Row load sharing from the sun's torsion with an equalising carrier (rows.md §2).",
             "No friction: load sharing is elastic.",
             "Not modelled: gear mesh errors, bending of the planets' pins, dynamic loads."],
}

REFERENCES = {
    "pins": [
        "Prudnikov A. P., «Потери мощности в контакте цевок и зубьев планетарной передачи типа K-H-V» (Power losses "
        "in pins and teeth contact area of KHV-type planetary gearing), Машиностроение "
        "(seed 000_fe288dec6e7c72f0.txt).",
        "Malhotra S. K., Parameswaran M. A., \"Analysis of a cycloid speed reducer\", Mech. Mach. Theory "
        "18(6):491–499, 1983.",
        "Blagojević M. et al., \"Influence of the friction on the cycloidal speed reducer efficiency\", "
        "J. Balkan Tribol. Assoc. 18(2):217–227, 2012.",
        "Chen B., Fang T., Li C., Wang S., \"Gear geometry of cycloid drives\", Science in China Series E 51, 2008.",
        "Sensinger J. W., \"Unified approach to cycloid drive profile, stress, and efficiency optimization\", "
        "J. Mech. Des. 132(2):024503, 2010.",
        "Gorla C. et al., \"Theoretical and experimental analysis of a cycloidal speed reducer\", J. Mech. Des. "
        "130(11):112604, 2008.",
        "Johnson K. L., Contact Mechanics, Cambridge University Press, 1985, §4.2.",
    ],
    "zstk": [
        "Merko M. A. et al., closed rolling-body mechanisms (seed file 003_2d1da402cb0b8488.txt).",
        "Johnson K. L., Contact Mechanics, Cambridge University Press, 1985, §4.2.",
        "Young W. C., Budynas R. G., Roark's Formulas for Stress and Strain, contact stresses, cylinder on cylinder.",
        "ISO 76, Rolling bearings — Static load ratings (4000 MPa for roller bearings).",
        "ISO/TS 16281:2008 and DIN 26281, roller stiffness 35 948·L_we^(8/9).",
        "Harris T. A., Kotzalas M. N., Rolling Bearing Analysis (Palmgren's line-contact deflection).",
        "Coxeter H. S. M., Greitzer S. L., Geometry Revisited, MAA, 1967 (Steiner chains).",
    ],
    "rows": [
        "Seed file 004_971077b94d8d4426.txt: a Russian journal paper on multi-row planetary gears (title and "
        "authors not recoverable); its ref. [1]: Plekhanov F. I., «Зубчатые планетарные передачи».",
    ],
}


def _g(v) -> str:
    return "—" if v is None else f"{v:.6g}" if isinstance(v, float) else str(v)


def method_lines(rec) -> list[tuple[str, str]]:
    """(equation with the design's values, reference) for the design's kind."""
    s, d = rec.result.summary, rec.design
    if rec.kind == "zstk":
        return _zstk(s, d, (rec.result.detail or {}).get("rollers") or [])
    if rec.kind == "pins":
        return _pins(s, d)
    if rec.kind == "rows":
        return [(f"K = max_N w_N / w̄ = {_g(s.get('K'))} (row {_g(s.get('K_row'))}, model {_g(s.get('model'))})",
                 "rows.md §2.2 [paper]"),
                (f"K_stepwise = {_g(s.get('K_stepwise'))}, K_exact = {_g(s.get('K_exact'))}, "
                 f"K_continuous = {_g(s.get('K_continuous'))}", "rows.md §3"),
                (f"w_max = K·w̄ = {_g(s.get('w_max_N_per_mm'))} N/mm, w̄ = {_g(s.get('w_mean_N_per_mm'))} N/mm",
                 "rows.md §2.2")]
    return []


def _zstk(s, d, rollers) -> list[tuple[str, str]]:
    lines = []
    i = s.get("sigma_max_roller")
    row = rollers[i] if isinstance(i, int) and 0 <= i < len(rollers) else None
    m, g = d.get("material", {}), d.get("geometry", {})
    if row is not None and m:
        inner = s.get("sigma_max_contact") == "inner"
        E1, n1, E2, n2 = m.get("roller_E_MPa"), m.get("roller_poisson"), m.get("ring_E_MPa"), m.get("ring_poisson")
        F = row["F_B_N"] if inner else row["F_H_N"]
        rho = row["rho_B_mm"] if inner else row["rho_H_mm"]
        L, r = g.get("roller_length_mm"), row["r_mm"]
        R = s["inner_raceway_radius_mm"] if inner else s["outer_raceway_radius_mm"]
        if None not in (E1, n1, E2, n2, L):
            k = math.sqrt(E1 * E2 / (math.pi * (E1 * (1 - n2 ** 2) + E2 * (1 - n1 ** 2))))
            p0 = k * math.sqrt(F / (L * rho))
            lines += [
                (f"ρ = r·R/(R {'+' if inner else '−'} r) = {_g(r)}·{_g(R)}/({_g(R)} {'+' if inner else '−'} {_g(r)})"
                 f" = {_g(rho)} mm", "Merko et al. eq. (4)" if inner else "Merko et al. eq. (5)"),
                (f"k = √(E_i·E/(π·[E_i(1 − μ²) + E(1 − μ_i²)])) = {_g(k)} √MPa", "Merko et al. eq. (7)"),
                (f"σ = k·√(F/(l·ρ)) = {_g(k)}·√({_g(F)}/({_g(L)}·{_g(rho)})) = {_g(p0)} MPa "
                 f"(reported σ_max = {_g(s.get('sigma_max_MPa'))} MPa, roller {i}, {s.get('sigma_max_contact')})",
                 "Merko et al. eqs. (3), (6); Johnson 1985 §4.2 (Hertz p0)"),
            ]
    lines.append((f"N* = {_g(s.get('N_star'))}, N = {_g(s.get('N'))}; corrected {s.get('correction')}: "
                  f"{_g(s.get('correction_mm'))} mm", "zstk.md §3.2"))
    lines.append((f"safety factor = [σ_H]/σ_max = {_g(s.get('allowable_stress_MPa'))}/{_g(s.get('sigma_max_MPa'))}"
                  f" = {_g(s.get('safety_factor'))}", "zstk.md §5"))
    return lines


def _pins(s, d) -> list[tuple[str, str]]:
    lines = []
    if s.get("loss_ratio") is not None:
        lines += [(f"λ̄ = (1/T_p)∫ μ_eff·Σ|l_i|·|ρ_i − R_b| / Σ l_i² dθ = {_g(s.get('loss_ratio'))}",
                   "pins.md §4.6 [derived]"),
                  (f"P̄_loss = λ̄·T_V·|ω_V| = {_g(s.get('loss_mean_W'))} W; efficiency = {_g(s.get('efficiency'))} "
                   f"({s.get('mode')})", "pins.md §4.6")]
    if s.get("P_tr_W") is not None:
        lines.append((f"F_tr1 = {_g(s.get('F_tr1_N'))} N, F_tr2 = {_g(s.get('F_tr2_N'))} N; P_tr1 = "
                      f"{_g(s.get('P_tr1_W'))} W, P_tr2 = {_g(s.get('P_tr2_W'))} W; P_tr = {_g(s.get('P_tr_W'))} W",
                      "Prudnikov eqs. (3)–(7)"))
    if s.get("pin_loss_bound_W") is not None:
        lines.append((f"P_i,max ≤ F_max·|ω|_max·(f_c r + f_k) = {_g(s.get('pin_loss_bound_W'))} W "
                      f"(peak force {_g(s.get('pin_force_max_N'))} N)", "Prudnikov eq. (7); pins.md §10"))
    if s.get("contact_stress_max_MPa") is not None:
        lines.append((f"p0 = √(F·E*/(π·l·ρ)) at the critical contact = {_g(s.get('contact_stress_max_MPa'))} MPa",
                      "Johnson 1985 §4.2 (Hertz line contact)"))
    return lines
