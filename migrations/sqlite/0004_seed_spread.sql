-- moorfret campaign store, SQLite backend, schema version 4: the seed-to-seed spread.
-- Released migrations are never edited: later changes go into new files.

UPDATE schema_info SET value = '4' WHERE key = 'schema_version';

-- The per-sea-state views of schema version 3 with the seed-to-seed spread of the damage rate
-- (`damage_rate_variance`: sample variance over the counted seeds, n - 1 in the denominator,
-- NULL for a single seed), and the lifetime views with the variance of their estimate:
--   D = sum_c p_c * year * mean_c,  Var(D) = sum_c (p_c * year)^2 * s_c^2 / n_c
-- over the sea states c with n_c >= 2 seeds (a single seed gives no spread; those sea states
-- are counted in `sea_states_without_spread`), and sum_c v_c^2 / (n_c - 1) with
-- v_c = (p_c * year)^2 * s_c^2 / n_c, from which the Welch-Satterthwaite degrees of freedom
-- Var(D)^2 / sum_c v_c^2 / (n_c - 1) follow. The square roots (standard deviation, standard
-- error, band) are taken by the readers: SQLite has no sqrt.
DROP VIEW lifetime_damage;
DROP VIEW sea_state_damage_inputs;
DROP VIEW lifetime_class_damage;
DROP VIEW sea_state_class_damage_inputs;

CREATE VIEW sea_state_damage_inputs AS
WITH r AS (
    SELECT d.sea_state_id, d.hot_spot_index, d.measure, d.damage, d.effective_duration_s,
           d.damage / d.effective_duration_s AS rate, d.fidelity
    FROM counted_damage_inputs d
), g AS (
    SELECT sea_state_id, hot_spot_index, measure, AVG(rate) AS mean_rate
    FROM r GROUP BY sea_state_id, hot_spot_index, measure
)
SELECT s.campaign_id,
       s.id AS sea_state_id,
       s.sea_state_index,
       s.hs_m,
       s.tp_s,
       s.occurrence_fraction,
       r.hot_spot_index,
       r.measure,
       COUNT(*) AS seeds,
       AVG(r.damage) AS damage_seed_mean,
       AVG(r.effective_duration_s) AS effective_duration_s,
       AVG(r.rate) AS damage_rate_per_s,
       CASE WHEN COUNT(*) > 1
            THEN SUM((r.rate - g.mean_rate) * (r.rate - g.mean_rate)) / (COUNT(*) - 1)
       END AS damage_rate_variance,
       CASE WHEN MIN(r.fidelity) = MAX(r.fidelity) THEN MIN(r.fidelity) ELSE 'mixed' END
           AS fidelity
FROM r
JOIN g ON g.sea_state_id = r.sea_state_id AND g.hot_spot_index = r.hot_spot_index
      AND g.measure = r.measure
JOIN sea_states s ON s.id = r.sea_state_id
GROUP BY s.campaign_id, s.id, s.sea_state_index, s.hs_m, s.tp_s, s.occurrence_fraction,
         r.hot_spot_index, r.measure;

CREATE VIEW lifetime_damage AS
SELECT campaign_id,
       hot_spot_index,
       measure,
       SUM(occurrence_fraction * 31557600.0 * damage_rate_per_s) AS annual_damage,
       SUM(occurrence_fraction) AS occurrence_covered,
       COUNT(*) AS sea_states,
       SUM(CASE WHEN seeds > 1
                THEN (occurrence_fraction * 31557600.0) * (occurrence_fraction * 31557600.0)
                     * damage_rate_variance / seeds
                ELSE 0.0 END) AS annual_damage_variance,
       SUM(CASE WHEN seeds > 1
                THEN (occurrence_fraction * 31557600.0) * (occurrence_fraction * 31557600.0)
                     * damage_rate_variance / seeds
                     * (occurrence_fraction * 31557600.0) * (occurrence_fraction * 31557600.0)
                     * damage_rate_variance / seeds / (seeds - 1)
                ELSE 0.0 END) AS annual_damage_variance_dof_sum,
       SUM(CASE WHEN seeds > 1 THEN 1 ELSE 0 END) AS sea_states_with_spread,
       SUM(CASE WHEN seeds > 1 THEN 0 ELSE 1 END) AS sea_states_without_spread
FROM sea_state_damage_inputs
GROUP BY campaign_id, hot_spot_index, measure;

CREATE VIEW sea_state_class_damage_inputs AS
WITH r AS (
    SELECT c.*, m.measure,
           CASE WHEN m.measure = 'fretting_max' THEN c.fretting_damage_rate_max_per_s
                ELSE c.fretting_damage_rate_mean_per_s END AS rate
    FROM counted_class_damage_inputs c
    CROSS JOIN (SELECT 'fretting_max' AS measure UNION ALL SELECT 'fretting_mean' AS measure) m
), g AS (
    SELECT sea_state_id, hot_spot_index, layer_interface, angular_position, measure,
           AVG(rate) AS mean_rate
    FROM r GROUP BY sea_state_id, hot_spot_index, layer_interface, angular_position, measure
)
SELECT s.campaign_id,
       s.id AS sea_state_id,
       s.sea_state_index,
       s.hs_m,
       s.tp_s,
       s.occurrence_fraction,
       r.hot_spot_index,
       r.layer_interface,
       r.angular_position,
       r.measure,
       COUNT(*) AS seeds,
       MAX(r.contacts) AS contacts,
       AVG(r.effective_duration_s) AS effective_duration_s,
       AVG(r.rate) AS damage_rate_per_s,
       AVG(r.effective_duration_s * r.rate) AS damage_seed_mean,
       CASE WHEN COUNT(*) > 1
            THEN SUM((r.rate - g.mean_rate) * (r.rate - g.mean_rate)) / (COUNT(*) - 1)
       END AS damage_rate_variance,
       AVG(r.stick_cycles_per_hour) AS stick_cycles_per_hour,
       AVG(r.partial_slip_cycles_per_hour) AS partial_slip_cycles_per_hour,
       AVG(r.gross_slip_cycles_per_hour) AS gross_slip_cycles_per_hour,
       MAX(r.ruiz_f1_max) AS ruiz_f1_max,
       MAX(r.ruiz_f2_max) AS ruiz_f2_max,
       MAX(r.peak_pressure_max_pa) AS peak_pressure_max_pa,
       MAX(r.slip_amplitude_max_m) AS slip_amplitude_max_m,
       CASE WHEN MIN(r.fidelity) = MAX(r.fidelity) THEN MIN(r.fidelity) ELSE 'mixed' END
           AS fidelity
FROM r
JOIN g ON g.sea_state_id = r.sea_state_id AND g.hot_spot_index = r.hot_spot_index
      AND g.layer_interface = r.layer_interface AND g.angular_position = r.angular_position
      AND g.measure = r.measure
JOIN sea_states s ON s.id = r.sea_state_id
GROUP BY s.campaign_id, s.id, s.sea_state_index, s.hs_m, s.tp_s, s.occurrence_fraction,
         r.hot_spot_index, r.layer_interface, r.angular_position, r.measure;

CREATE VIEW lifetime_class_damage AS
SELECT campaign_id,
       hot_spot_index,
       layer_interface,
       angular_position,
       measure,
       SUM(occurrence_fraction * 31557600.0 * damage_rate_per_s) AS annual_damage,
       SUM(occurrence_fraction) AS occurrence_covered,
       COUNT(*) AS sea_states,
       SUM(CASE WHEN seeds > 1
                THEN (occurrence_fraction * 31557600.0) * (occurrence_fraction * 31557600.0)
                     * damage_rate_variance / seeds
                ELSE 0.0 END) AS annual_damage_variance,
       SUM(CASE WHEN seeds > 1
                THEN (occurrence_fraction * 31557600.0) * (occurrence_fraction * 31557600.0)
                     * damage_rate_variance / seeds
                     * (occurrence_fraction * 31557600.0) * (occurrence_fraction * 31557600.0)
                     * damage_rate_variance / seeds / (seeds - 1)
                ELSE 0.0 END) AS annual_damage_variance_dof_sum,
       SUM(CASE WHEN seeds > 1 THEN 1 ELSE 0 END) AS sea_states_with_spread,
       SUM(CASE WHEN seeds > 1 THEN 0 ELSE 1 END) AS sea_states_without_spread
FROM sea_state_class_damage_inputs
GROUP BY campaign_id, hot_spot_index, layer_interface, angular_position, measure;
