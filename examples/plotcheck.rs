use rigfit::eval::*;
fn main() {
    let problem = rigfit::fixtures::reference_problem();
    let p = problem.model.params().len();
    let n = 512;
    let mut params = Vec::new();
    for i in 0..n {
        let mut v = rigfit::model::tensile::REFERENCE.to_vec();
        v[4] *= 1.0 + 0.001 * i as f64;
        params.extend(v);
    }
    let batch = Batch {
        candidates: n,
        params: vec![params],
        offsets: vec![vec![0.0; n]],
    };
    for threads in [1, 2] {
        let mut ev = CpuEvaluator::new(problem.clone(), threads);
        let t = std::time::Instant::now();
        let s = ev.fitness(&batch).unwrap();
        let dt = t.elapsed().as_secs_f64();
        let steps = (problem.experiments[0].window.end - 1) * problem.substeps;
        println!(
            "threads {threads}: {:.3e} cand-steps/s, best {:.3e}",
            (n * steps) as f64 / dt,
            s.values.iter().cloned().fold(1.0, f64::min)
        );
    }
}
