//! `POST /api/fit?name=FILE`: the family fitted to an uploaded target (the
//! body: an OBJ, OFF, PLY file or a PNG picture), as `bcifs fit` fits it.

use super::{Answer, Explorer, Query, time_budget};

/// The largest upload taken.
pub(super) const UPLOAD_LIMIT: u64 = 64 << 20;

impl Explorer {
    /// The fit's report (`bcifs fit --json`), or why it was refused; stopped at the time budget
    /// with the best member so far.
    pub(super) fn fit(&self, query: &Query, body: &[u8]) -> Answer {
        let Some(name) = query.get("name").filter(|n| !n.is_empty()) else {
            return Answer::error(400, "`name`: the uploaded file's name (its extension says its format)");
        };
        let points = match bcifs::render::read_target_bytes(name, body, &self.design) {
            Ok(points) => points,
            Err(e) => return Answer::error(422, e),
        };
        let target =
            bcifs::render::FitTarget { points, free_pose: bcifs::render::is_picture(name), ..Default::default() };
        let cancel = bcifs::render::Cancel::new();
        let timer = cancel.clone();
        let budget = time_budget();
        // The time budget stops the search: the answer is then its best member so far.
        std::thread::spawn(move || {
            std::thread::sleep(budget.min(std::time::Duration::from_secs(3600)));
            timer.cancel();
        });
        let options = bcifs::render::FitOptions { cancel, starts: 2, ..Default::default() };
        match bcifs::render::fit(&self.design, &target, &options) {
            Ok(report) => Answer::json(&report.to_json()),
            Err(e) => Answer::error(422, e),
        }
    }
}
