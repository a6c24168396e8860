-- moorfret campaign store, PostgreSQL backend, schema version 2: damage inputs per contact class.
-- Released migrations are never edited: later changes go into new files.

UPDATE schema_info SET value = '2' WHERE key = 'schema_version';

-- One row per strand job, hot spot and contact class (layer interface × angular position):
-- what `fretting::inputs` computes for one (sea state, seed, hot spot). Rates are per second
-- and cycle counts per hour of effective (run-in excluded) simulated time; cycle counts and the
-- histogram are summed over the contacts of the class.
CREATE TABLE class_damage_inputs (
    job_id                          BIGINT NOT NULL REFERENCES jobs (id) ON DELETE CASCADE,
    hot_spot_index                  BIGINT NOT NULL,
    layer_interface                 BIGINT NOT NULL CHECK (layer_interface >= 0),
    angular_position                TEXT NOT NULL
        CHECK (angular_position IN ('neutral_axis', 'between', 'outer_arc')),
    seed_index                      BIGINT NOT NULL,
    effective_duration_s            DOUBLE PRECISION NOT NULL CHECK (effective_duration_s > 0.0),
    contacts                        BIGINT NOT NULL CHECK (contacts > 0),
    fretting_damage_rate_max_per_s  DOUBLE PRECISION NOT NULL,
    fretting_damage_rate_mean_per_s DOUBLE PRECISION NOT NULL,
    stick_cycles_per_hour           DOUBLE PRECISION NOT NULL,
    partial_slip_cycles_per_hour    DOUBLE PRECISION NOT NULL,
    gross_slip_cycles_per_hour      DOUBLE PRECISION NOT NULL,
    ruiz_f1_max                     DOUBLE PRECISION NOT NULL,
    ruiz_f2_max                     DOUBLE PRECISION NOT NULL,
    peak_pressure_max_pa            DOUBLE PRECISION NOT NULL,
    slip_amplitude_max_m            DOUBLE PRECISION NOT NULL,
    histogram_json                  TEXT NOT NULL,
    PRIMARY KEY (job_id, hot_spot_index, layer_interface, angular_position)
);
CREATE INDEX class_damage_inputs_class
    ON class_damage_inputs (hot_spot_index, layer_interface, angular_position);

-- Per sea state, hot spot, contact class and fretting measure (`fretting_max`: the most damaged
-- contact of the class; `fretting_mean`: the mean over its contacts): seed means over the done
-- strand jobs. damage_seed_mean is the damage over effective_duration_s.
CREATE VIEW sea_state_class_damage_inputs AS
SELECT s.campaign_id,
       s.id AS sea_state_id,
       s.sea_state_index,
       s.hs_m,
       s.tp_s,
       s.occurrence_fraction,
       c.hot_spot_index,
       c.layer_interface,
       c.angular_position,
       m.measure,
       COUNT(*) AS seeds,
       MAX(c.contacts) AS contacts,
       AVG(c.effective_duration_s) AS effective_duration_s,
       AVG(CASE WHEN m.measure = 'fretting_max' THEN c.fretting_damage_rate_max_per_s
                ELSE c.fretting_damage_rate_mean_per_s END) AS damage_rate_per_s,
       AVG(c.effective_duration_s * CASE WHEN m.measure = 'fretting_max'
                THEN c.fretting_damage_rate_max_per_s
                ELSE c.fretting_damage_rate_mean_per_s END) AS damage_seed_mean,
       AVG(c.stick_cycles_per_hour) AS stick_cycles_per_hour,
       AVG(c.partial_slip_cycles_per_hour) AS partial_slip_cycles_per_hour,
       AVG(c.gross_slip_cycles_per_hour) AS gross_slip_cycles_per_hour,
       MAX(c.ruiz_f1_max) AS ruiz_f1_max,
       MAX(c.ruiz_f2_max) AS ruiz_f2_max,
       MAX(c.peak_pressure_max_pa) AS peak_pressure_max_pa,
       MAX(c.slip_amplitude_max_m) AS slip_amplitude_max_m
FROM class_damage_inputs c
JOIN jobs j ON j.id = c.job_id AND j.state = 'done' AND j.kind <> 'test'
JOIN sea_states s ON s.id = j.sea_state_id
CROSS JOIN (SELECT 'fretting_max' AS measure UNION ALL SELECT 'fretting_mean' AS measure) m
GROUP BY s.campaign_id, s.id, s.sea_state_index, s.hs_m, s.tp_s, s.occurrence_fraction,
         c.hot_spot_index, c.layer_interface, c.angular_position, m.measure;

-- Annual fretting damage per hot spot, contact class and measure: Σ over sea states of
-- occurrence × (one Julian year / T_eff) × seed-mean damage, as `lifetime_damage`; the covered
-- fraction of the year beside it, never renormalised.
CREATE VIEW lifetime_class_damage AS
SELECT campaign_id,
       hot_spot_index,
       layer_interface,
       angular_position,
       measure,
       SUM(occurrence_fraction * 31557600.0 * damage_rate_per_s) AS annual_damage,
       SUM(occurrence_fraction) AS occurrence_covered,
       COUNT(*) AS sea_states
FROM sea_state_class_damage_inputs
GROUP BY campaign_id, hot_spot_index, layer_interface, angular_position, measure;
