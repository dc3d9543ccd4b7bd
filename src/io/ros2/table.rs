//! [`IdTable`]: a bag's schemas, channels and odometry by their `u16` ids,
//! kept sorted in one vector (a bag has tens of topics; a map type per use
//! would cost the wasm more than the lookups it saves).

/// The most ids a table holds: a bag records tens of topics, and a table
/// past this is a hostile file's.
pub const MAX_IDS: usize = 1024;

/// Values by `u16` id, sorted by id.
#[derive(Debug, Clone)]
pub struct IdTable<V> {
    rows: Vec<(u16, V)>,
}

impl<V> Default for IdTable<V> {
    fn default() -> Self {
        Self { rows: Vec::new() }
    }
}

impl<V> IdTable<V> {
    fn find(&self, id: u16) -> Result<usize, usize> {
        self.rows.binary_search_by_key(&id, |r| r.0)
    }

    pub fn get(&self, id: u16) -> Option<&V> {
        self.find(id).ok().map(|i| &self.rows[i].1)
    }

    pub fn get_mut(&mut self, id: u16) -> Option<&mut V> {
        self.find(id).ok().map(move |i| &mut self.rows[i].1)
    }

    /// Puts `value` at `id` (replacing one there): false, and nothing
    /// added, when the table is full.
    pub fn insert(&mut self, id: u16, value: V) -> bool {
        match self.find(id) {
            Ok(i) => self.rows[i].1 = value,
            Err(_) if self.rows.len() >= MAX_IDS => return false,
            Err(i) => self.rows.insert(i, (id, value)),
        }
        true
    }

    pub fn iter(&self) -> impl Iterator<Item = (u16, &V)> {
        self.rows.iter().map(|(id, v)| (*id, v))
    }

    pub fn values_mut(&mut self) -> impl Iterator<Item = &mut V> {
        self.rows.iter_mut().map(|(_, v)| v)
    }
}
