-- moorfret campaign store, SQLite backend, schema version 1.
-- Released migrations are never edited: later changes go into new files.
-- Times are integer milliseconds since the Unix epoch (UTC); JSON is stored as TEXT.

CREATE TABLE schema_info (
    key   TEXT PRIMARY KEY NOT NULL,
    value TEXT NOT NULL
);
INSERT INTO schema_info (key, value) VALUES ('schema_version', '1');

CREATE TABLE campaigns (
    id            INTEGER PRIMARY KEY,
    name          TEXT NOT NULL UNIQUE,
    spec_json     TEXT NOT NULL,
    spec_sha256   TEXT NOT NULL,
    state         TEXT NOT NULL DEFAULT 'active' CHECK (state IN ('active', 'cancelled')),
    created_at_ms INTEGER NOT NULL
);

CREATE TABLE sea_states (
    id                  INTEGER PRIMARY KEY,
    campaign_id         INTEGER NOT NULL REFERENCES campaigns (id) ON DELETE CASCADE,
    sea_state_index     INTEGER NOT NULL,
    hs_m                REAL NOT NULL,
    tp_s                REAL NOT NULL,
    occurrence_fraction REAL NOT NULL CHECK (occurrence_fraction >= 0.0 AND occurrence_fraction <= 1.0),
    seeds_json          TEXT NOT NULL,
    UNIQUE (campaign_id, sea_state_index)
);

CREATE TABLE workers (
    id              TEXT PRIMARY KEY NOT NULL,
    host            TEXT NOT NULL,
    pid             INTEGER NOT NULL,
    version         TEXT NOT NULL,
    started_at_ms   INTEGER NOT NULL,
    last_seen_at_ms INTEGER NOT NULL
);

CREATE TABLE jobs (
    id                  INTEGER PRIMARY KEY,
    campaign_id         INTEGER NOT NULL REFERENCES campaigns (id) ON DELETE CASCADE,
    sea_state_id        INTEGER REFERENCES sea_states (id) ON DELETE CASCADE,
    kind                TEXT NOT NULL,
    state               TEXT NOT NULL
        CHECK (state IN ('blocked', 'ready', 'running', 'done', 'failed', 'cancelled')),
    payload_json        TEXT NOT NULL,
    attempt             INTEGER NOT NULL DEFAULT 0,
    max_attempts        INTEGER NOT NULL CHECK (max_attempts >= 1),
    lost_count          INTEGER NOT NULL DEFAULT 0,
    lease_token         TEXT,
    lease_expires_at_ms INTEGER,
    heartbeat_at_ms     INTEGER,
    worker_id           TEXT REFERENCES workers (id),
    priority            INTEGER NOT NULL DEFAULT 0,
    expected_cost_s     REAL NOT NULL DEFAULT 0.0,
    cache_key           TEXT,
    result_json         TEXT,
    result_sha256       TEXT,
    cached_from_job_id  INTEGER REFERENCES jobs (id),
    error_class         TEXT,
    error_message       TEXT,
    not_before_ms       INTEGER NOT NULL DEFAULT 0,
    created_at_ms       INTEGER NOT NULL,
    updated_at_ms       INTEGER NOT NULL
);
CREATE INDEX jobs_ready_order ON jobs (priority DESC, id) WHERE state = 'ready';
CREATE INDEX jobs_running_lease ON jobs (lease_expires_at_ms) WHERE state = 'running';
CREATE INDEX jobs_campaign_state ON jobs (campaign_id, state);
CREATE INDEX jobs_sea_state ON jobs (sea_state_id);
CREATE INDEX jobs_cache_done ON jobs (cache_key) WHERE state = 'done' AND cache_key IS NOT NULL;

CREATE TABLE job_dependencies (
    job_id     INTEGER NOT NULL REFERENCES jobs (id) ON DELETE CASCADE,
    depends_on INTEGER NOT NULL REFERENCES jobs (id) ON DELETE CASCADE,
    PRIMARY KEY (job_id, depends_on),
    CHECK (job_id <> depends_on)
);
CREATE INDEX job_dependencies_upstream ON job_dependencies (depends_on);

CREATE TABLE attempts (
    id            INTEGER PRIMARY KEY,
    job_id        INTEGER NOT NULL REFERENCES jobs (id) ON DELETE CASCADE,
    claim_number  INTEGER NOT NULL,
    lease_token   TEXT NOT NULL UNIQUE,
    worker_id     TEXT NOT NULL REFERENCES workers (id),
    host          TEXT NOT NULL,
    pid           INTEGER NOT NULL,
    started_at_ms INTEGER NOT NULL,
    ended_at_ms   INTEGER,
    outcome       TEXT CHECK (outcome IS NULL OR outcome IN
        ('done', 'cached', 'transient_failure', 'permanent_failure', 'lost', 'cancelled')),
    error_message TEXT
);
CREATE INDEX attempts_job ON attempts (job_id);

CREATE TABLE artifacts (
    sha256        TEXT PRIMARY KEY NOT NULL,
    size_bytes    INTEGER NOT NULL,
    path          TEXT NOT NULL,
    created_at_ms INTEGER NOT NULL
);

CREATE TABLE job_artifacts (
    job_id INTEGER NOT NULL REFERENCES jobs (id) ON DELETE CASCADE,
    role   TEXT NOT NULL,
    sha256 TEXT NOT NULL REFERENCES artifacts (sha256),
    PRIMARY KEY (job_id, role)
);

-- Results. Keys are indexed columns; the per-row payload is JSON while its layout still moves.
CREATE TABLE hot_spot_summaries (
    job_id         INTEGER NOT NULL REFERENCES jobs (id) ON DELETE CASCADE,
    hot_spot_index INTEGER NOT NULL,
    summary_json   TEXT NOT NULL,
    PRIMARY KEY (job_id, hot_spot_index)
);

CREATE TABLE contact_statistics (
    job_id            INTEGER NOT NULL REFERENCES jobs (id) ON DELETE CASCADE,
    hot_spot_index    INTEGER NOT NULL,
    contact_index     INTEGER NOT NULL,
    layer_interface   INTEGER NOT NULL,
    angular_position_rad REAL NOT NULL,
    statistics_json   TEXT NOT NULL,
    PRIMARY KEY (job_id, hot_spot_index, contact_index)
);
CREATE INDEX contact_statistics_class ON contact_statistics (hot_spot_index, layer_interface);

CREATE TABLE damage_inputs (
    job_id               INTEGER NOT NULL REFERENCES jobs (id) ON DELETE CASCADE,
    hot_spot_index       INTEGER NOT NULL,
    measure              TEXT NOT NULL,
    seed_index           INTEGER NOT NULL,
    effective_duration_s REAL NOT NULL CHECK (effective_duration_s > 0.0),
    damage               REAL NOT NULL,
    details_json         TEXT NOT NULL,
    PRIMARY KEY (job_id, hot_spot_index, measure)
);
CREATE INDEX damage_inputs_class ON damage_inputs (hot_spot_index, measure);

-- Views users query. Rows of the test-only job kind never reach them.
CREATE VIEW campaign_progress AS
SELECT c.id AS campaign_id,
       c.name AS campaign_name,
       c.state AS campaign_state,
       (SELECT COUNT(*) FROM jobs j WHERE j.campaign_id = c.id) AS jobs_total,
       (SELECT COUNT(*) FROM jobs j WHERE j.campaign_id = c.id AND j.state = 'blocked') AS jobs_blocked,
       (SELECT COUNT(*) FROM jobs j WHERE j.campaign_id = c.id AND j.state = 'ready') AS jobs_ready,
       (SELECT COUNT(*) FROM jobs j WHERE j.campaign_id = c.id AND j.state = 'running') AS jobs_running,
       (SELECT COUNT(*) FROM jobs j WHERE j.campaign_id = c.id AND j.state = 'done') AS jobs_done,
       (SELECT COUNT(*) FROM jobs j WHERE j.campaign_id = c.id AND j.state = 'failed') AS jobs_failed,
       (SELECT COUNT(*) FROM jobs j WHERE j.campaign_id = c.id AND j.state = 'cancelled') AS jobs_cancelled,
       (SELECT COALESCE(SUM(s.occurrence_fraction), 0.0) FROM sea_states s
         WHERE s.campaign_id = c.id) AS occurrence_planned,
       -- A sea state is covered once it has jobs and every one of them is done.
       (SELECT COALESCE(SUM(s.occurrence_fraction), 0.0) FROM sea_states s
         WHERE s.campaign_id = c.id
           AND EXISTS (SELECT 1 FROM jobs j WHERE j.sea_state_id = s.id)
           AND NOT EXISTS (SELECT 1 FROM jobs j WHERE j.sea_state_id = s.id AND j.state <> 'done'))
         AS occurrence_covered
FROM campaigns c;

-- Per sea state, hot spot and damage measure: the seed mean of the damage accumulated over the
-- effective (run-in excluded) simulated time.
CREATE VIEW sea_state_damage_inputs AS
SELECT s.campaign_id,
       s.id AS sea_state_id,
       s.sea_state_index,
       s.hs_m,
       s.tp_s,
       s.occurrence_fraction,
       d.hot_spot_index,
       d.measure,
       COUNT(*) AS seeds,
       AVG(d.damage) AS damage_seed_mean,
       AVG(d.effective_duration_s) AS effective_duration_s,
       AVG(d.damage / d.effective_duration_s) AS damage_rate_per_s
FROM damage_inputs d
JOIN jobs j ON j.id = d.job_id AND j.state = 'done' AND j.kind <> 'test'
JOIN sea_states s ON s.id = j.sea_state_id
GROUP BY s.campaign_id, s.id, s.sea_state_index, s.hs_m, s.tp_s, s.occurrence_fraction,
         d.hot_spot_index, d.measure;

-- Annual damage: sum over sea states of occurrence × (one Julian year / T_eff) × seed-mean damage
-- (docs/damage.md), taken per seed as the damage rate so seeds of unequal T_eff weigh correctly.
-- The covered fraction of the year is reported beside it, never renormalised.
CREATE VIEW lifetime_damage AS
SELECT campaign_id,
       hot_spot_index,
       measure,
       SUM(occurrence_fraction * 31557600.0 * damage_rate_per_s)
           AS annual_damage,
       SUM(occurrence_fraction) AS occurrence_covered,
       COUNT(*) AS sea_states
FROM sea_state_damage_inputs
GROUP BY campaign_id, hot_spot_index, measure;
