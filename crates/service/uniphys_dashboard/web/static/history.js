/**
 * The overview's history of stage samples, kept client side: the first poll brings every sample
 * the server has, later polls only those after the last one held (`since_ms`). At most `cap`
 * samples are kept, oldest dropped first.
 */

export class History {
  constructor(cap = 720) {
    this.cap = cap;
    /** `{at_ms, stages: [{stage, depth, running, failed, throughput_per_sec}]}`, oldest first. */
    this.samples = [];
  }

  /** `at_ms` of the newest sample held: the next poll's `since_ms`; null before the first. */
  get lastAtMs() {
    return this.samples.length ? this.samples[this.samples.length - 1].at_ms : null;
  }

  /** Appends the samples newer than the newest held (oldest first), then trims to the cap. */
  append(samples) {
    for (const sample of samples ?? []) {
      const last = this.lastAtMs;
      if (last === null || sample.at_ms > last) this.samples.push(sample);
    }
    if (this.samples.length > this.cap) this.samples.splice(0, this.samples.length - this.cap);
  }

  /** Every stage name seen in the held samples. */
  stageNames() {
    const names = new Set();
    for (const sample of this.samples) for (const s of sample.stages) names.add(s.stage);
    return names;
  }

  /** `[[at_ms, value]]` of `field` (`depth`, `throughput_per_sec`, …) for `stage`. */
  points(stage, field) {
    const points = [];
    for (const sample of this.samples) {
      const entry = sample.stages.find((s) => s.stage === stage);
      if (entry && typeof entry[field] === 'number') points.push([sample.at_ms, entry[field]]);
    }
    return points;
  }
}
