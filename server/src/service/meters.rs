//! The process's metrics (prometheus-client): histograms of job durations,
//! queue waits and request latencies, counters of requests and of worker
//! deaths, the gauge of busy workers, and the gauge of jobs by state that
//! `/metrics` reads from storage when scraped. Memory is fixed per label set (a histogram is its
//! buckets), however many jobs and requests pass.

use prometheus_client::encoding::EncodeLabelSet;
use prometheus_client::metrics::counter::Counter;
use prometheus_client::metrics::family::Family;
use prometheus_client::metrics::gauge::Gauge;
use prometheus_client::metrics::histogram::Histogram;
use prometheus_client::registry::Registry;

/// The label of a job state.
#[derive(Clone, Debug, Hash, PartialEq, Eq, EncodeLabelSet)]
pub struct StateLabel {
    /// queued, running, done, failed, cancelled.
    pub state: String,
}

/// The label of a queue lane.
#[derive(Clone, Debug, Hash, PartialEq, Eq, EncodeLabelSet)]
pub struct LaneLabel {
    /// `short` or `long` (by the job's cost).
    pub lane: &'static str,
}

/// The labels of a request.
#[derive(Clone, Debug, Hash, PartialEq, Eq, EncodeLabelSet)]
pub struct RequestLabels {
    /// The route's template (`/api/v1/jobs/{id}`), or `unmatched`.
    pub route: String,
    /// The response's status.
    pub status: u16,
}

/// The label of a worker death.
#[derive(Clone, Debug, Hash, PartialEq, Eq, EncodeLabelSet)]
pub struct ReasonLabel {
    /// `memory_limit` or `worker_crashed`.
    pub reason: &'static str,
}

/// Job durations and queue waits (ms): 10 ms to 5 min.
const JOB_BUCKETS_MS: [f64; 10] = [
    10.0, 30.0, 100.0, 300.0, 1000.0, 3000.0, 10000.0, 30000.0, 100000.0, 300000.0,
];

/// Request latencies (ms): 1 ms to 10 s.
const REQUEST_BUCKETS_MS: [f64; 9] = [1.0, 3.0, 10.0, 30.0, 100.0, 300.0, 1000.0, 3000.0, 10000.0];

fn job_histogram() -> Histogram {
    Histogram::new(JOB_BUCKETS_MS)
}

fn request_histogram() -> Histogram {
    Histogram::new(REQUEST_BUCKETS_MS)
}

/// The metric families of one process, registered once.
pub struct Meters {
    registry: Registry,
    /// Jobs by state (all processes: set from storage at each scrape).
    pub jobs: Family<StateLabel, Gauge>,
    /// Durations of the jobs this process ran, by lane.
    pub job_duration_ms: Family<LaneLabel, Histogram, fn() -> Histogram>,
    /// Queue waits (submission to start) of the jobs this process started.
    pub job_queue_wait_ms: Family<LaneLabel, Histogram, fn() -> Histogram>,
    /// Requests by route and status.
    pub http_requests: Family<RequestLabels, Counter>,
    /// Request latencies (to the response head) by route.
    pub http_request_duration_ms: Family<RequestLabels, Histogram, fn() -> Histogram>,
    /// Deaths of this process's worker processes while running a job.
    pub worker_deaths: Family<ReasonLabel, Counter>,
    /// Workers of this process running a job now.
    pub busy_workers: Gauge,
}

impl Meters {
    /// New families, registered.
    pub fn new() -> Meters {
        let jobs = Family::<StateLabel, Gauge>::default();
        let job_duration_ms = Family::new_with_constructor(job_histogram as fn() -> Histogram);
        let job_queue_wait_ms = Family::new_with_constructor(job_histogram as fn() -> Histogram);
        let http_requests = Family::<RequestLabels, Counter>::default();
        let http_request_duration_ms =
            Family::new_with_constructor(request_histogram as fn() -> Histogram);
        let worker_deaths = Family::<ReasonLabel, Counter>::default();
        let busy_workers = Gauge::default();
        let mut registry = Registry::default();
        registry.register(
            "nvector_jobs",
            "Jobs by state (all processes sharing the database)",
            jobs.clone(),
        );
        registry.register(
            "nvector_job_duration_ms",
            "Duration of the jobs this process ran, by lane",
            job_duration_ms.clone(),
        );
        registry.register(
            "nvector_job_queue_wait_ms",
            "Time from submission to start of the jobs this process started, by lane",
            job_queue_wait_ms.clone(),
        );
        registry.register(
            "nvector_http_requests",
            "Requests by route and status",
            http_requests.clone(),
        );
        registry.register(
            "nvector_http_request_duration_ms",
            "Time to the response head, by route and status",
            http_request_duration_ms.clone(),
        );
        registry.register(
            "nvector_worker_deaths",
            "Worker processes of this process that died running a job, by reason",
            worker_deaths.clone(),
        );
        registry.register(
            "nvector_busy_workers",
            "Workers of this process running a job now",
            busy_workers.clone(),
        );
        Meters {
            registry,
            jobs,
            job_duration_ms,
            job_queue_wait_ms,
            http_requests,
            http_request_duration_ms,
            worker_deaths,
            busy_workers,
        }
    }

    /// The OpenMetrics text of every family.
    pub fn encode(&self) -> String {
        let mut out = String::new();
        // Writing to a String cannot fail.
        let _ = prometheus_client::encoding::text::encode(&mut out, &self.registry);
        out
    }
}

/// The lane of a job of this cost under this short-job cost.
pub fn lane(cost: i64, short_cost: i64) -> LaneLabel {
    LaneLabel {
        lane: if cost <= short_cost { "short" } else { "long" },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_text_keeps_the_documented_names() {
        let m = Meters::new();
        m.jobs
            .get_or_create(&StateLabel {
                state: "done".into(),
            })
            .set(3);
        m.job_duration_ms.get_or_create(&lane(5, 10)).observe(42.0);
        m.http_requests
            .get_or_create(&RequestLabels {
                route: "/healthz".into(),
                status: 200,
            })
            .inc();
        let text = m.encode();
        assert!(text.contains("nvector_jobs{state=\"done\"} 3"), "{text}");
        assert!(
            text.contains("nvector_job_duration_ms_bucket{le=\"100.0\",lane=\"short\"} 1")
                || text.contains("nvector_job_duration_ms_bucket{lane=\"short\",le=\"100.0\"} 1"),
            "{text}"
        );
        assert!(
            text.contains("nvector_http_requests_total{route=\"/healthz\",status=\"200\"} 1"),
            "{text}"
        );
        assert!(text.ends_with("# EOF\n"), "{text}");
    }
}
