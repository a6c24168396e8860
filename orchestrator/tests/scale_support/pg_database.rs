//! A PostgreSQL database of its own for a test that runs worker processes, which connect by
//! URL and so cannot be given a schema of their own. Dropped by [`TempDatabase::finish`].

use std::net::SocketAddr;

use sqlx::postgres::PgConnectOptions;
use sqlx::{ConnectOptions, Connection};

/// A freshly created database on the test server.
pub struct TempDatabase {
    /// Its name.
    pub name: String,
    admin: PgConnectOptions,
}

impl TempDatabase {
    /// Creates `mf_<uuid>` through the server at `admin_url` (whose user may create databases).
    pub async fn create(admin_url: &str) -> Self {
        let admin: PgConnectOptions = admin_url.parse().expect("admin URL");
        let name = format!("mf_{}", uuid::Uuid::new_v4().simple());
        let mut conn = admin.connect().await.expect("connect as admin");
        sqlx::query(&format!("CREATE DATABASE {name}"))
            .execute(&mut conn)
            .await
            .expect("create database");
        conn.close().await.expect("close admin connection");
        Self { name, admin }
    }

    /// URL of the database through the server's own address.
    pub fn url(&self) -> String {
        let addr = format!("{}:{}", self.admin.get_host(), self.admin.get_port());
        self.url_via(&addr)
    }

    /// URL of the database reached at `addr` (a forwarder), same user; trust or `.pgpass`
    /// authentication is assumed.
    pub fn url_via(&self, addr: &str) -> String {
        format!(
            "postgres://{}@{addr}/{}",
            self.admin.get_username(),
            self.name
        )
    }

    /// The server's address, for a forwarder to connect to.
    pub fn server_addr(&self) -> SocketAddr {
        let host = match self.admin.get_host() {
            "localhost" => "127.0.0.1",
            other => other,
        };
        format!("{host}:{}", self.admin.get_port())
            .parse()
            .expect("server host must be an IP address")
    }

    /// Drops the database, disconnecting whoever is still on it.
    pub async fn finish(self) {
        let mut conn = self.admin.connect().await.expect("connect as admin");
        sqlx::query(&format!(
            "DROP DATABASE IF EXISTS {} WITH (FORCE)",
            self.name
        ))
        .execute(&mut conn)
        .await
        .expect("drop database");
        let _ = conn.close().await;
    }
}
