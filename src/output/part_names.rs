//! The one table of readable part names every figure prints (issue 44 §2):
//! the plots' legends and bar labels, the placement picture's legends and
//! the frame strip's key show `windshield rail, left`, not the identifier
//! `windshield_rail_left` the legend file and the tables keep. Tables and
//! CSV files keep the identifiers (they are keys other programs join on).

/// Words printed differently from their identifier form.
const WORDS: [(&str, &str); 6] =
    [("a", "A"), ("b", "B"), ("c", "C"), ("d", "D"), ("ehmi", "eHMI"), ("hmi", "HMI")];

/// Sides and ends that read as a qualifier after a comma
/// (`door_front_left` → "front door, left").
const SIDES: [&str; 2] = ["left", "right"];

/// Nouns that identifiers name before their position (`door_front`): they
/// are read after it ("front door").
const NOUN_FIRST: [&str; 3] = ["door", "window", "seat"];

/// The readable name of part (or candidate) identifier `name`: underscores
/// become spaces, a trailing side becomes ", left", a one-letter word joins
/// its noun (`b_pillar` → "B-pillar"), and a patch's centre
/// (`front_bumper@x2.95y-0.76z0.46`) is said in metres.
pub fn readable_part_name(name: &str) -> String {
    if let Some((part, rest)) = name.split_once('@') {
        // `part@xXyYzZ` or `part@WxH@xXyYzZ` (a display patch of that size).
        let (size, centre) = match rest.rsplit_once('@') {
            Some((size, centre)) => (readable_size(size), centre),
            None => (None, rest),
        };
        let at = readable_centre(centre).unwrap_or_else(|| rest.to_string());
        let size = size.map_or_else(String::new, |size| format!(" {size}"));
        return format!("{} patch{size} at {at}", readable_part_name(part));
    }
    let mut words: Vec<String> = name
        .split(['_', '-', ' '])
        .filter(|w| !w.is_empty())
        .map(|w| {
            WORDS.iter().find(|(from, _)| w.eq_ignore_ascii_case(from)).map_or(w, |(_, to)| to).to_string()
        })
        .collect();
    if words.is_empty() {
        return name.to_string();
    }
    let side = (words.len() > 1 && SIDES.contains(&words[words.len() - 1].as_str())).then(|| words.pop());
    if words.len() == 2
        && NOUN_FIRST.contains(&words[0].as_str())
        && ["front", "rear"].contains(&words[1].as_str())
    {
        words.swap(0, 1);
    }
    let mut text = String::new();
    for (index, word) in words.iter().enumerate() {
        if index > 0 {
            let joined =
                words[index - 1].len() == 1 && words[index - 1].chars().all(|c| c.is_ascii_uppercase());
            text.push(if joined { '-' } else { ' ' });
        }
        text.push_str(word);
    }
    match side.flatten() {
        Some(side) => format!("{text}, {side}"),
        None => text,
    }
}

/// `0.3x0.2` → "0.3 × 0.2 m"; `None` when not that form.
fn readable_size(size: &str) -> Option<String> {
    let (width, height) = size.split_once('x')?;
    let (width, height) = (width.parse::<f64>().ok()?, height.parse::<f64>().ok()?);
    Some(format!("{width} × {height} m"))
}

/// `x2.95y-0.76z0.46` → "(2.95, −0.76, 0.46) m"; `None` when not that form.
fn readable_centre(centre: &str) -> Option<String> {
    let rest = centre.strip_prefix('x')?;
    let (x, rest) = rest.split_once('y')?;
    let (y, z) = rest.split_once('z')?;
    let numbers: Vec<f64> = [x, y, z].iter().map(|v| v.parse::<f64>().ok()).collect::<Option<_>>()?;
    let say = |v: f64| format!("{v}").replace('-', "−");
    Some(format!("({}, {}, {}) m", say(numbers[0]), say(numbers[1]), say(numbers[2])))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn identifiers_read_as_words_with_the_side_last() {
        assert_eq!(readable_part_name("windshield_rail_left"), "windshield rail, left");
        assert_eq!(readable_part_name("door_front_right"), "front door, right");
        assert_eq!(readable_part_name("b_pillar_left"), "B-pillar, left");
        assert_eq!(readable_part_name("grill"), "grill");
        assert_eq!(readable_part_name("front_license_plate"), "front license plate");
        assert_eq!(readable_part_name("left"), "left");
        assert_eq!(readable_part_name(""), "");
    }

    #[test]
    fn a_patch_says_its_part_and_its_centre_in_metres() {
        assert_eq!(
            readable_part_name("front_bumper@x2.95y-0.76z0.46"),
            "front bumper patch at (2.95, −0.76, 0.46) m"
        );
        assert_eq!(readable_part_name("hood@centre"), "hood patch at centre");
        assert_eq!(
            readable_part_name("door_front_left@0.3x0.2@x1y0.5z1"),
            "front door, left patch 0.3 × 0.2 m at (1, 0.5, 1) m"
        );
    }
}
