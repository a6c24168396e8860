//! Load histories of the strand studies: a `time_s,tension_n,curvature_per_m` file, or hot
//! spot 0 of a `moorfret run global` hot-spot file (`tension_n_0`, `curvature_per_m_0`).

/// The (t, T, κ) columns of `path` with t in [from, to].
pub fn read_load(
    path: &str,
    from: f64,
    to: f64,
) -> Result<[Vec<f64>; 3], Box<dyn std::error::Error>> {
    let text = std::fs::read_to_string(path)?;
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().ok_or("empty load file")?.split(',').collect();
    let col = |names: &[&str]| {
        header
            .iter()
            .position(|h| names.contains(&h.trim()))
            .ok_or(format!("{path}: no column {names:?}"))
    };
    let it = col(&["time_s"])?;
    let iten = col(&["tension_n", "tension_n_0"])?;
    let ik = col(&["curvature_per_m", "curvature_per_m_0"])?;
    let mut out = [Vec::new(), Vec::new(), Vec::new()];
    for (n, line) in lines.enumerate() {
        let v: Vec<f64> = line
            .split(',')
            .map(|x| x.trim().parse::<f64>())
            .collect::<Result<_, _>>()
            .map_err(|e| format!("{path}: line {}: {e}", n + 2))?;
        let field = |i: usize| {
            v.get(i)
                .copied()
                .ok_or(format!("{path}: line {}: too few columns", n + 2))
        };
        let t = field(it)?;
        if t >= from && t <= to {
            out[0].push(t);
            out[1].push(field(iten)?);
            out[2].push(field(ik)?);
        }
    }
    Ok(out)
}
